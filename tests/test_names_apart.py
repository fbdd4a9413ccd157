"""Names a user chooses never merge two things of the semantics (found by trying names a user
may well pick). Each case failed before the rules named actions and processes apart:

* two input events whose names capitalise alike (``tooFar``, ``TooFar``) both made
  ``TooFarToDModel``: the Isabelle theory kept one definition and stated
  ``SendToDModel = (TooFarToDModel ||| TooFarToDModel)``, so the second event never reached the
  d-model, and check-theory found nothing wrong;
* an input event ``send`` made a second ``SendToDModel``, an operation ``receive`` a second
  ``ReceiveFromDModel`` (the text printed ``SendToDModel ≙ SendToDModel``);
* a mapping named like an action (``Init``), like the p-model, or like the d-model, and a
  d-model and a p-model of one name, gave two processes or two definitions of one name
  (check-theory: T-DUPLICATE; the text: ``process DCMotorBase ≙ (… ⟦…⟧ DCMotorBase)``).

The oracle is the theory's own structure, read back from the generated text (which
definition sends which event), and ``cyphy check-theory``'s duplicate check, which cites
Isabelle's rule that a constant is declared once.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from cyphy.api import (SemanticsGenOptions, check_theory, generate_cyphycircus,
                       generate_isabelle)
from cyphy.diagnostics import Severity

ROOT = Path(__file__).resolve().parent.parent
DCMOTOR = ROOT / "examples" / "dcmotor"
PENDULUM = ROOT / "tests" / "data" / "heldout" / "pendulum"


def _renamed(tmp_path: Path, source: Path, old: str, new: str) -> Path:
    """A copy of a model folder with the whole word ``old`` replaced by ``new`` in its files."""
    folder = tmp_path / source.name
    shutil.copytree(source, folder)
    for path in folder.iterdir():
        if path.suffix in (".rsm", ".toml"):
            path.write_text(re.sub(rf"\b{old}\b", new, path.read_text()))
    return folder


def _session(folder: Path, out: Path, dialect: str = "utp") -> dict[str, str]:
    """The generated session's files, written to ``out``; check-theory must accept them."""
    generated = generate_isabelle([folder], SemanticsGenOptions(dialect=dialect))
    assert not generated.report.has_errors, generated.report.diagnostics
    out.mkdir()
    for name, text in generated.files.items():
        (out / name).write_text(text if isinstance(text, str) else text.decode())
    result = check_theory(out)
    assert not result.findings, [str(f) for f in result.findings]
    return {n: t for n, t in generated.files.items() if isinstance(t, str)}


def _definitions(theory: str) -> dict[str, str]:
    """Each ``definition NAME … where "NAME … = BODY"`` of a utp theory: name → body."""
    found = re.findall(r'^definition (\w+) ::.*?where\s*\n?\s*"\1[^=]*= (.*?)"\n', theory,
                       re.M | re.S)
    names = [n for n, _ in found]
    assert len(names) == len(set(names)), names
    return dict(found)


def _theory(files: dict[str, str]) -> str:
    return next(t for n, t in files.items() if n.endswith("_CyPhyCircus.thy"))


@pytest.mark.parametrize("second", ["TooFar", "send"])
def test_every_input_event_is_sent_to_the_dmodel(tmp_path: Path, second: str) -> None:
    """The pendulum's two input events, the second renamed: SendToDModel runs one action per
    event, and each action communicates its own event."""
    folder = _renamed(tmp_path, PENDULUM, "tooBack", second)
    defs = _definitions(_theory(_session(folder, tmp_path / "out")))
    sent = re.findall(r"\w+", defs["SendToDModel"].replace("|||", " "))
    assert len(sent) == 2 and len(set(sent)) == 2, defs["SendToDModel"]
    channels = {re.search(r"registerRead_(\w+)!", defs[a]).group(1) for a in sent}
    assert channels == {"tooFar", second}


def test_an_operation_named_receive_keeps_its_call(tmp_path: Path) -> None:
    """An operation ``receive`` makes ``ReceiveFromDModel`` apart from the loop of that name,
    and the loop still receives it."""
    folder = _renamed(tmp_path, PENDULUM, "push", "receive")
    defs = _definitions(_theory(_session(folder, tmp_path / "out")))
    receivers = [n for n, body in defs.items() if "registerWrite_receive" in body]
    assert receivers and receivers != ["ReceiveFromDModel"], receivers
    assert f"{receivers[0]} ;; Y" in defs["ReceiveFromDModel"]
    text = generate_cyphycircus([folder], "text", SemanticsGenOptions()).files
    cpc = next(t for n, t in text.items() if n.endswith(".cpc"))
    assert not re.search(r"^\s*(\w+) ≙ \1\s*$", cpc, re.M)  # no action defined as itself


@pytest.mark.parametrize("mapping", ["Init", "Evolve", "tock", "DCMotorBase", "DCMotorSoftware",
                                     "DCMotorSoftwareMain"])
def test_a_mapping_named_like_a_part_of_the_semantics(tmp_path: Path, mapping: str) -> None:
    """The composition takes the mapping's name unless something else has it; both dialects
    load (check-theory), and the text's three processes are distinct."""
    folder = _renamed(tmp_path, DCMOTOR, "BenchMapping", mapping)
    theory = _theory(_session(folder, tmp_path / "utp"))
    system = re.search(r'^definition (\w+) :: "\w+ process"', theory, re.M).group(1)
    assert system == f"{mapping}_2"
    _session(folder, tmp_path / "ax", "axiomatic")
    text = generate_cyphycircus([folder], "text", SemanticsGenOptions()).files
    cpc = next(t for n, t in text.items() if n.endswith(".cpc"))
    processes = re.findall(r"^process (\w+)", cpc, re.M)
    assert len(processes) == 3 and len(set(processes)) == 3, processes


def test_a_dmodel_and_a_pmodel_of_one_name(tmp_path: Path) -> None:
    """A d-model module named like the p-model: two processes, two state types."""
    folder = _renamed(tmp_path, DCMOTOR, "DCMotorSoftware", "DCMotorBase")
    theory = _theory(_session(folder, tmp_path / "utp"))
    assert re.search(r"^alphabet DCMotorBaseState =", theory, re.M)
    assert re.search(r"^alphabet DCMotorBase_2State =", theory, re.M)
    composition = re.search(r'BenchMapping = HideCSP \(\(state (\w+) \\<bullet> (\w+)\)', theory)
    assert composition.groups() == ("DCMotorBase_2State", "DCMotorBase_2Main")
    _session(folder, tmp_path / "ax", "axiomatic")


def test_a_parameter_named_as_a_port_is_refused(tmp_path: Path) -> None:
    """An operation parameter named ``Motor_das``, the name the semantics gives the motor's
    ``das``: the theory's call read ``Motor_das = Motor_das`` and set nothing. Refused at the
    mapping's operation (simulate, which keeps the two apart, still runs it)."""
    folder = _renamed(tmp_path, DCMOTOR, "w", "Motor_das")
    generated = generate_isabelle([folder], SemanticsGenOptions())
    assert not generated.files
    [error] = [d for d in generated.report.diagnostics if d.severity == Severity.ERROR]
    assert error.code.id == "E-SEMANTICS" and "'Motor_das' of drive" in error.message
    assert error.span.line == next(
        i for i, line in enumerate((folder / "Mapping.rsm").read_text().splitlines(), 1)
        if "operation drive" in line)


def test_both_events_of_alike_names_drive_the_animated_theory(tmp_path: Path) -> None:
    """The oracle for the first case: the theory animated (``cyphy animate``, which reads
    only the theory) swings the pendulum as ``cyphy simulate`` does, switching both ways,
    which needs both events (``tooFar`` to push back, ``TooFar`` to push forward again)."""
    import numpy as np

    from test_heldout import _column, _simulate, _worst, _writes
    from cyphy.verify.animate.animation import animate

    folder = _renamed(tmp_path, PENDULUM, "tooBack", "TooFar")
    _session(folder, tmp_path / "out")
    animation = animate(tmp_path / "out", 1.5, {}, {"tscale": 0.05}, samples=31)
    simulated = _simulate(folder, folder / "swing.toml", "--t-end", "1.5", "--samples", "31")
    worst = _worst(animation, simulated, ["Pivot_theta", "Pivot_v"])
    assert max(worst.values()) < 0.01, worst
    pushes = _writes(animation, "push")
    assert (0.3, -0.3) in pushes and (0.65, 0.3) in pushes  # back on tooFar, on on TooFar
    assert np.max(np.abs(_column(animation, "Pivot_theta"))) > 0.3
