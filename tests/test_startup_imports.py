"""``cyphy check`` and ``cyphy gen --sdf`` start without the heavy libraries, and so does
``cyphy gen --isabelle`` once its equations of motion are cached: SymPy, SciPy and
matplotlib each cost a large part of a second before the first line is read, NumPy (with its
BLAS) 0.1-0.3 s of processor time, Lark 75 ms (issue 24's start-up budget;
``benchmarks/bench_startup.py`` measures the whole processes). The model's vectors and
matrices are pure-Python values (``cyphy.model.array``) for that reason, and Lark is loaded
only when a file is not in the parse cache."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
HEAVY = ("sympy", "scipy", "matplotlib", "numpy")
#: cyphy's own packages that neither command needs: the other topics of the API, which
#: ``cyphy.api`` loads on first use only (they pull in the semantics, Z3, Jinja, SymPy).
UNNEEDED = ("cyphy.api.semantics", "cyphy.api.simulate", "cyphy.api.solve", "cyphy.api.view",
            "cyphy.api.machines", "cyphy.semantics.circus", "cyphy.semantics.dynamics",
            "cyphy.semantics.machines", "cyphy.backends.isabelle", "cyphy.backends.circus",
            "cyphy.verify.flowstar.build", "cyphy.verify.flowstar.export",
            "cyphy.verify.flowstar.problem", "cyphy.verify.flowstar.scenario",
            "cyphy.verify.flowstar.controller",
            # the other commands' modules: the parser is built for the command named only
            "cyphy.cli.show", "cyphy.cli.solve", "cyphy.cli.simulate", "cyphy.cli.reach",
            "cyphy.cli.view", "cyphy.cli.lsp", "cyphy.cli.check_theory", "cyphy.cli.animate")

#: Runs the command in this process, then prints the modules it imported.
_WRAPPER = """
import json, sys
from cyphy.cli import main
code = main(sys.argv[1:])
print(json.dumps([code, sorted(sys.modules)]))
"""


def _imported_modules(args: list[str], cache: Path | None = None) -> tuple[int, set[str]]:
    """The exit status and the modules imported; ``cache`` is cyphy's cache folder (else the
    default one, warm after the first run)."""
    env = {"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}
    if cache is not None:
        env["CYPHY_CACHE_DIR"] = str(cache)
    done = subprocess.run([sys.executable, "-c", _WRAPPER, *args], cwd=ROOT, text=True,
                          capture_output=True, timeout=300, env=env)
    code, modules = json.loads(done.stdout.strip().splitlines()[-1])
    return code, set(modules)


def _imported(args: list[str], cache: Path | None = None) -> tuple[int, set[str]]:
    """The exit status and the top-level packages imported."""
    code, modules = _imported_modules(args, cache)
    return code, {m.split(".")[0] for m in modules}


@pytest.mark.parametrize("args", [
    ["check", "examples/marxbot"],
    ["gen", "examples/marxbot", "--sdf", "-o", "{tmp}"],
])
def test_command_imports_no_heavy_library(args: list[str], tmp_path: Path) -> None:
    code, modules = _imported([a.format(tmp=tmp_path) for a in args])
    assert code == 0
    assert "cyphy.api" not in modules  # the names are top-level packages only
    assert "cyphy" in modules
    assert modules.isdisjoint(HEAVY), sorted(modules & set(HEAVY))


@pytest.mark.parametrize("args", [
    ["check", "examples/marxbot"],
    ["gen", "examples/marxbot", "--sdf", "-o", "{tmp}"],
])
def test_command_imports_only_its_part_of_the_api(args: list[str], tmp_path: Path) -> None:
    code, modules = _imported_modules([a.format(tmp=tmp_path) for a in args])
    assert code == 0
    loaded = sorted(m for m in modules if m.startswith(UNNEEDED))
    assert not loaded, loaded


@pytest.mark.parametrize("args", [
    ["check", "examples/marxbot"],
    ["gen", "examples/marxbot", "--sdf", "-o", "{tmp}"],
])
def test_a_warm_cache_reads_no_grammar(args: list[str], tmp_path: Path) -> None:
    """Lark is loaded to parse a file that is not in the parse cache, and only then: the first
    run (an empty cache) imports it, the second (every file cached) does not."""
    argv = [a.format(tmp=tmp_path / "out") for a in args]
    cache = tmp_path / "cache"
    code, cold = _imported(argv, cache)
    assert code == 0 and "lark" in cold
    code, warm = _imported(argv, cache)
    assert code == 0 and "lark" not in warm


#: What a warm ``gen --isabelle`` does not need: the tree's numbers and the algorithms over
#: it (NumPy), the translator to SymPy, the printers of the other semantic targets.
ISABELLE_UNNEEDED = ("cyphy.semantics.dynamics.rigid_body", "cyphy.semantics.dynamics.spatial",
                     "cyphy.semantics.dynamics.tree_numbers", "cyphy.translate.to_sympy",
                     "cyphy.backends.circus.latex", "cyphy.backends.circus.text")


def test_a_warm_gen_isabelle_imports_no_heavy_library(tmp_path: Path) -> None:
    """The main job with its equations of motion cached (every run after the first): the
    kinematic tree is built and keyed as data, so neither NumPy nor SymPy is imported, nor
    the algorithms, nor another target's printer. The first run (an empty cache) derives the
    equations with both: the probe is not blind."""
    argv = ["gen", "examples/marxbot", "--isabelle", "-o", str(tmp_path / "out")]
    cache = tmp_path / "cache"
    code, cold = _imported_modules(argv, cache)
    assert code == 0 and {"numpy", "sympy"} <= {m.split(".")[0] for m in cold}
    code, warm = _imported_modules(argv, cache)
    assert code == 0
    heavy = {m.split(".")[0] for m in warm} & set(HEAVY)
    assert not heavy, sorted(heavy)
    loaded = sorted(m for m in warm if m.startswith(ISABELLE_UNNEEDED))
    assert not loaded, loaded


def test_the_probe_sees_a_heavy_import(tmp_path: Path) -> None:
    """The probe is not blind: ``solve`` reduces with SymPy, the URDF export computes principal
    axes with NumPy, and the wrapper reports them."""
    code, modules = _imported(["solve", "examples/dcmotor"])
    assert code == 0 and "sympy" in modules
    code, modules = _imported(["gen", "examples/marxbot", "--urdf", "-o", str(tmp_path)])
    assert code == 0 and "numpy" in modules
    code, modules = _imported_modules(["solve", "examples/dcmotor"])
    assert code == 0 and "cyphy.api.solve" in modules


@pytest.mark.parametrize("argv", [
    ["check", "examples/marxbot", "--format", "json", "--const", "A=1"],
    ["-q", "gen", "examples/marxbot", "--sdf", "-o", "out", "--target", "gazebo"],
    ["--warnings-as-errors", "check-theory", "session"],
    ["simulate", "examples/dcmotor", "--t-end", "2", "-q"],
])
def test_the_parser_of_the_command_named_reads_as_the_whole_one(argv: list[str]) -> None:
    """The parser built for one command (``_parser(argv)``) holds that command alone and
    gives the same values as the parser of every command."""
    from cyphy.cli import COMMANDS, _parser

    lean, whole = _parser(argv), _parser()
    assert vars(lean.parse_args(argv)) == vars(whole.parse_args(argv))
    assert len(lean._subparsers._group_actions[0].choices) == 1  # type: ignore[union-attr]
    assert len(whole._subparsers._group_actions[0].choices) == len(COMMANDS)  # type: ignore


@pytest.mark.parametrize("argv", [["--help"], ["chek"], ["--vers"], ["check_theory"], []])
def test_anything_but_a_command_gets_the_whole_parser(argv: list[str]) -> None:
    """Help, a misspelt command, an abbreviated option: the parser that lists every command
    answers (what it prints is the same as before)."""
    from cyphy.cli import COMMANDS, _parser

    choices = _parser(argv)._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    assert len(choices) == len(COMMANDS)


def test_the_lazy_facade_exports_the_entry_points() -> None:
    """Every name of ``cyphy.api.__all__`` is the function or class of its topic, also when
    a topic named like its entry point (``semantics``, ``simulate``, ``solve``, ``view``) was
    imported as a module first: the import system binds that module on the package."""
    probe = """
import json, types
import cyphy.api.semantics, cyphy.api.simulate, cyphy.api.solve, cyphy.api.view
from cyphy import api
print(json.dumps({n: isinstance(getattr(api, n), types.ModuleType) for n in api.__all__}))
"""
    done = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, text=True,
                          capture_output=True, timeout=300,
                          env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"})
    is_module = json.loads(done.stdout.strip().splitlines()[-1])
    assert {"check", "semantics", "simulate", "solve", "view", "check_theory"} <= set(is_module)
    assert not any(is_module.values()), sorted(n for n, m in is_module.items() if m)


_ENV_PROBE = """
import os, sys
import cyphy.cli
cyphy.cli.main = lambda: print(os.environ.get("OPENBLAS_NUM_THREADS")) or 0
cyphy.cli.run()
"""


@pytest.mark.parametrize("given, expected", [(None, "1"), ("3", "3")])
def test_the_command_keeps_openblas_to_one_thread_unless_told(given: str | None,
                                                              expected: str) -> None:
    """OpenBLAS's spinning threads cost every NumPy-importing command a tenth of a second of
    processor time; the ``cyphy`` process asks for one thread before anything imports NumPy,
    and a user's own setting wins."""
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if given is not None:
        env["OPENBLAS_NUM_THREADS"] = given
    env["PYTHONPATH"] = str(ROOT)
    out = subprocess.run([sys.executable, "-c", _ENV_PROBE], env=env, capture_output=True,
                         text=True, timeout=60, check=True)
    assert out.stdout.strip() == expected



def test_simulate_numeric_imports_no_sympy(tmp_path: Path) -> None:
    """``simulate --numeric`` (issue 31: a 10-link chain in a second as a whole command)
    integrates the tree with Pinocchio and SciPy: SymPy (0.5-1 s to import) and matplotlib
    stay out, whatever the scenario machinery that ``cyphy.api.simulate`` imports."""
    args = ["simulate", "examples/manipulator", "--numeric", "--t-end", "0.1", "-q",
            "-o", str(tmp_path / "out.csv")]
    code, modules = _imported(args)
    assert code == 0
    assert "scipy" in modules and "numpy" in modules  # the probe sees the integrator
    assert modules.isdisjoint({"sympy", "matplotlib"}), sorted(modules & {"sympy",
                                                                          "matplotlib"})
