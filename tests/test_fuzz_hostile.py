"""Hostile values in real models (issue 20): a fixed-seed fuzz of a few hundred mutants of our
example models, with numbers beyond a double, non-finite results, deep nesting, huge index
ranges and cycles put where numbers and members go. Every command run on them ends with a
status of 0, 1 or 2 and diagnostics: never an internal error (70), a traceback, or 20 s."""

from __future__ import annotations

import contextlib
import io
import random
import re
import time
from pathlib import Path

import pytest

from conftest import EXAMPLES
from cyphy.cli import main
from cyphy.deep import run_deep

SEED = 20
MUTANTS = 240
BLOCK = re.compile(r"(?:local (?:link|body|sensor|actuator|joint) \w+|pmodel \w+|"
                   r"[jsa]ref \w+ = \w+) *\{")
NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:[eE][+-]?\d+)?(?![\w.])")

HOSTILE_VALUES = [
    "1e309", "-1e309", "1e308*10", "1e155", "1" + "0" * 400, "0/0", "1/0", "sqrt(-1)",
    "log(0)", "exp(1000)", "2^100000", "(-8)^(1/3)", "+".join(["0.001"] * 600),
    "(" * 400 + "0.1" + ")" * 400, "(1+" * 300 + "1" + ")" * 300, "-" * 200 + "1",
    "K_SELF", "0", "-0.5", "10^10^10", "2^1100",
]
HOSTILE_MEMBERS = [
    "index i : [0, 1000000000)", "index i : [0, 100000]", "index j : [5, 0)",
    "index k : [0, 1e309)", "const K_SELF : real = K_SELF + 1",
    "const CA : real = CB const CB : real = CA", "pose { x = 1e309 y = 0/0 z = 0 roll = 0 "
    "pitch = 0 yaw = 0 }",
]


def mutant(rng: random.Random, text: str) -> str:
    """One to three hostile edits: a number replaced, or a member put at the start of a
    p-model, link, body, sensor, actuator or joint."""
    for _ in range(rng.randint(1, 3)):
        if rng.random() < 0.6:
            numbers = list(NUMBER.finditer(text))
            if numbers:
                m = rng.choice(numbers)
                text = text[:m.start()] + rng.choice(HOSTILE_VALUES) + text[m.end():]
                continue
        braces = [m.end() for m in BLOCK.finditer(text)]
        if braces:
            at = rng.choice(braces)
            text = text[:at] + "\n" + rng.choice(HOSTILE_MEMBERS) + "\n" + text[at:]
    return text


SOURCES = sorted(p for p in EXAMPLES.rglob("*.rsm") if p.parent.name != "faulty")
MODELS = {"marxbot": "marXbotBase", "dcmotor": "DCMotorBase", "manipulator": "Manipulator"}


def run_cli(argv: list[str]) -> tuple[int, str, float]:
    out, err = io.StringIO(), io.StringIO()
    start = time.monotonic()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = run_deep(lambda: main(argv))  # as the installed command runs
        except SystemExit as exit:
            code = exit.code if isinstance(exit.code, int) else 2
    return code, err.getvalue(), time.monotonic() - start


@pytest.mark.parametrize("batch", range(4))
def test_hostile_mutants_end_in_diagnostics(tmp_path: Path, batch: int,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CYPHY_MAX_COPIES", "2000")  # keep the elaborated mutants small
    rng = random.Random(SEED * 100 + batch)
    failures = []
    for n in range(MUTANTS // 4):
        source = rng.choice(SOURCES)
        folder = tmp_path / f"m{n}"
        folder.mkdir()
        for sibling in source.parent.glob("*.rsm"):  # the project folder, one file mutated
            text = sibling.read_text(encoding="utf-8")
            (folder / sibling.name).write_text(mutant(rng, text) if sibling == source else text,
                                               encoding="utf-8")
        command = rng.choice([["check"], ["check"], ["show"],
                              ["gen", "--sdf", "-o", str(folder / "out")]])
        if command[0] != "check":
            command += ["--model", MODELS[source.parent.name]]
        code, err, seconds = run_cli([*command, str(folder)])
        if code not in (0, 1, 2) or "Traceback" in err or "internal error" in err \
                or seconds > 20:
            failures.append((source.name, command[0], code, round(seconds, 1), err[-600:],
                             (folder / source.name).read_text()[:3000]))
    assert not failures, failures[:3]
