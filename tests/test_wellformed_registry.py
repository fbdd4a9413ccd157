"""Every condition of wellformedness.md is implemented, registered under its id, and listed
by `cyphy check --list-rules`."""

from __future__ import annotations

import re

import pytest

from cyphy.cli import main
from cyphy.wellformed import RULES
from conftest import ROOT


def _ids(prefix: str, n: int) -> list[str]:
    return [f"{prefix}{i}" for i in range(1, n + 1)]


EXPECTED = (["PM1", *_ids("L", 8), *_ids("B", 3), *_ids("J", 3), *_ids("SE", 3),
             *_ids("AC", 3), "JSA1", *_ids("Fix", 3), *_ids("Flex", 3), *_ids("P", 3),
             *_ids("IX", 2), "PO1", *_ids("AN", 4), *_ids("PMap", 12), *_ids("V", 5)])
# The state-machine conditions are cyphy's own (wellformedness.md covers p-models and mappings).
MACHINES = _ids("STM", 15)
# Conditions of issue 27, beyond wellformedness.md: indexed connections (element i to
# element i), unique qualified names, a non-zero joint axis, units (docs/modelling-checks.md);
# and of the mutation sweep: a mapping's index within its element's copies, no cycle of fixed
# connections; and of its second round: what a mapping's members say (a passed value never
# read, a typed input event's value never given, two mappings of one module and p-model, an
# input written twice, a derivative); and of the third: a mapping's units, a local at the
# top of a mapping.
OWN = ["IX3", "IX4", "V6", "U1", "IX5", "Fix4", "PMap13", "PMap14", "PMap15", "PMap16",
       "PMap17", "PMap18", "U2"]
SPEC = ROOT.parent / "shared" / "spec" / "wellformedness.md"


def test_registry_has_every_condition() -> None:
    assert sorted(RULES) == sorted(EXPECTED + MACHINES + OWN)


@pytest.mark.skipif(not SPEC.is_file(), reason="../shared/spec is absent")
def test_expected_ids_are_the_spec_ids() -> None:
    ids: set[str] = set()
    for row in re.findall(r"^\| ([A-Za-z]+\d+(?:-[A-Za-z]*\d+)?)(?: \(paper\))? \|",
                          SPEC.read_text(), re.M):
        m = re.fullmatch(r"([A-Za-z]+)(\d+)(?:-[A-Za-z]*(\d+))?", row)
        assert m is not None
        first, last = int(m.group(2)), int(m.group(3) or m.group(2))
        ids.update(f"{m.group(1)}{i}" for i in range(first, last + 1))
    ids -= {f"S{i}" for i in range(1, 6)}  # scope and typing: the front end's codes
    assert ids == set(EXPECTED)


def test_every_rule_has_a_docstring_and_summary() -> None:
    for r in RULES.values():
        assert r.summary and r.check.__doc__, r.id
        assert r.check.__name__.startswith(f"check_{r.id}_"), r.check.__name__


def test_list_rules(capsys) -> None:
    assert main(["check", "--list-rules"]) == 0
    lines = capsys.readouterr().out.splitlines()
    scope = ["S1", "S2", "S3", "S4", "S5"]  # checked by resolution and typing
    assert [line.split()[0] for line in lines] == scope + list(RULES)
    assert lines[0].split()[:2] == ["S1", "ERROR"]
    assert lines[len(scope)].split()[:2] == ["PM1", "ERROR"]
