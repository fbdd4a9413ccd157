"""Running Flow* on a model file and deciding what its output means (spec §2, §3).

Flow* reports SAFE for what it computed, even when the computation did not complete or
``max jumps`` cut the paths short, and exits 0 on a syntax error. A run therefore counts as
SAFE only when: the exit status is 0, stderr is empty, stdout says ``Computation
completed``, the verdict line says SAFE, and the model itself lists every mode under
``unsafe`` with ``max jumps`` large enough (:func:`model_problems`). An UNSAFE here is
Flow*'s word only: on a hybrid automaton its flowpipes may follow a branch no trajectory
takes, so :mod:`cyphy.verify.flowstar.check` reports it only with a simulated witness.
"""

from __future__ import annotations

import re
import subprocess
import tempfile
import time
from dataclasses import dataclass, replace
from pathlib import Path

from cyphy.verify.flowstar import processes
from cyphy.verify.flowstar.syntax import parse_model

_ANSI = re.compile(r"\x1b\[[0-9;]*m")
_VERDICT = re.compile(r"Result of (?:the )?safety verification(?: on the computed flowpipes)?"
                      r"\s*:\s*(SAFE|UNSAFE|UNKNOWN)")
_TIME = re.compile(r"(?:Total time cost|Time cost of flowpipe construction)\s*:\s*"
                   r"([0-9.eE+-]+)\s*seconds")
_COMPLETED = re.compile(r"Computation completed\s*:\s*(\d+)\s*flowpipe")
_NOT_COMPLETED = re.compile(r"Computation not completed\s*:\s*(\d+)\s*flowpipe")


@dataclass(frozen=True)
class Outcome:
    """``verdict`` is SAFE, UNSAFE, UNKNOWN, or ERROR (Flow* could not check the model)."""

    verdict: str
    reason: str
    seconds: float | None = None  # Flow*'s own time cost (CPU time), when it printed one
    counterexample: str = ""  # Flow*'s counterexamples/NAME.counterexample, when it wrote one
    flowpipes: int | None = None  # how many Flow* computed, when it said

    @property
    def exit_code(self) -> int:
        return {"SAFE": 0, "UNSAFE": 1, "UNKNOWN": 3}.get(self.verdict, 2)


def strip_ansi(text: str) -> str:
    return _ANSI.sub("", text)


def decide(returncode: int, stdout: str, stderr: str, problems: list[str] = ()) -> Outcome:
    """The verdict of one Flow* run from its exit status and outputs. ``problems`` are what
    :func:`model_problems` found in the model: any of them turns SAFE into UNKNOWN."""
    out, err = strip_ansi(stdout), strip_ansi(stderr).strip()
    m = _TIME.search(out)
    seconds = float(m.group(1)) if m else None
    if "Exception" in out and "Divided by 0" in out:
        return Outcome("UNKNOWN", "Flow* stopped: an enclosure of a divisor (or of a log or "
                       "sqrt argument) contains 0", seconds)
    if returncode < 0 or returncode > 1:
        return Outcome("ERROR", f"Flow* crashed (exit status {returncode})"
                       + (f": {_first_line(err)}" if err else ""), seconds)
    syntax = re.search(r"Error line \d+\s*:?\s*syntax error.*", err)
    if syntax:
        return Outcome("ERROR", f"Flow* rejected the model: {syntax.group(0).strip()}", seconds)
    if returncode == 1:
        return Outcome("ERROR", "Flow* rejected the model: " +
                       (_first_line(err) or _first_line(out) or "exit status 1"), seconds)
    verdict = _VERDICT.search(out)
    completed, not_completed = _COMPLETED.search(out), _NOT_COMPLETED.search(out)
    if verdict and verdict.group(1) == "UNSAFE":
        return Outcome("UNSAFE", "a flowpipe lies entirely in the unsafe set", seconds)
    if err:
        return Outcome("UNKNOWN", f"Flow* wrote to stderr: {_first_line(err)}", seconds)
    if not_completed:
        return Outcome("UNKNOWN", f"the computation did not complete ({not_completed.group(1)} "
                       "flowpipes): try a smaller step, a higher order or a larger remainder "
                       "estimate", seconds)
    if not completed:
        return Outcome("UNKNOWN", "Flow* did not say that the computation completed", seconds)
    if verdict is None:
        return Outcome("UNKNOWN", "Flow* printed no verdict (the model has no unsafe set?)",
                       seconds)
    if verdict.group(1) == "UNKNOWN":
        return Outcome("UNKNOWN", "some flowpipe overlaps the unsafe set partially (a real "
                       "violation or the over-approximation)", seconds)
    if problems:
        return Outcome("UNKNOWN", "Flow* said SAFE, but " + "; ".join(problems), seconds)
    return Outcome("SAFE", f"all {completed.group(1)} flowpipes avoid the unsafe set", seconds,
                   flowpipes=int(completed.group(1)))


def _first_line(text: str) -> str:
    return next((ln.strip() for ln in text.splitlines() if ln.strip()), "")


def model_problems(text: str, required_jumps: int | None = None) -> list[str]:
    """What would make Flow*'s SAFE on this model meaningless: a mode not listed under
    ``unsafe`` (it counts as entirely unsafe, or the check is vacuous), or ``max jumps``
    below what the horizon needs (the paths stop early, silently)."""
    model = parse_model(text)
    problems = []
    if model.unsafe is None:
        problems.append("the model has no unsafe set")
    elif model.kind == "hybrid":
        missing = [m for m in model.modes if not model.unsafe.get(m)]
        if missing:
            problems.append(f"mode{'s' if len(missing) > 1 else ''} {', '.join(missing)} "
                            "not listed (or empty) under unsafe")
    jumps = model.settings.get("max jumps")
    if required_jumps is not None and isinstance(jumps, int) and jumps < required_jumps:
        problems.append(f"max jumps {jumps} is below the {required_jumps} the horizon needs")
    return problems


class FlowstarMissing(Exception):
    """The Flow* executable cannot be found or started."""


def run_text(text: str, binary: str, timeout: float | None = None,
             required_jumps: int | None = None) -> Outcome:
    """Run Flow* on the model ``text`` (fed on stdin, as Flow* requires) in a scratch
    directory of its own (Flow* writes outputs/, images/ and counterexamples/ into the
    current one), and decide. On a timeout the whole process group is killed (Flow* may
    have started gnuplot)."""
    problems = model_problems(text, required_jumps)
    with tempfile.TemporaryDirectory(prefix="cyphy-flowstar-") as scratch:
        started = time.perf_counter()
        try:
            proc = processes.start([binary], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, cwd=scratch)
        except OSError as err:
            raise FlowstarMissing(f"cannot run {binary}: {err.strerror or err}") from None
        try:
            stdout, stderr = proc.communicate(text.encode("utf-8"), timeout=timeout)
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            return Outcome("UNKNOWN", f"Flow* did not finish within {timeout:g} s",
                           time.perf_counter() - started)
        except BaseException:
            _kill_group(proc)
            raise
        finally:
            processes.finished(proc)
        found = sorted(Path(scratch, "counterexamples").glob("*.counterexample"))
        counterexample = found[0].read_text(encoding="utf-8", errors="replace") if found \
            else ""
    outcome = decide(proc.returncode, stdout.decode("utf-8", "replace"),
                     stderr.decode("utf-8", "replace"), problems)
    return replace(outcome, counterexample=counterexample)


def _kill_group(proc: subprocess.Popen) -> None:
    """Kill Flow* and everything it started (its own session), then reap it."""
    processes.kill_group(proc)
    proc.communicate()
