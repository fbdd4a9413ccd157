"""The collector pause (cyphy/collector.py) and the fast pickling of syntax trees
(cyphy/pickling.py): what they promise besides speed."""

from __future__ import annotations

import gc
import os
import pickle
import subprocess
import sys
import weakref

import pytest
from conftest import EXAMPLES

from cyphy import collector
from cyphy.lang import ast
from cyphy.lang.parser import parse_text


class _Cycle:
    def __init__(self) -> None:
        self.me = self


def test_pause_disables_then_restores_the_collector() -> None:
    assert gc.isenabled()
    with collector.paused():
        assert not gc.isenabled()
        with collector.paused():  # nested: the inner pause must not re-enable
            pass
        assert not gc.isenabled()
    assert gc.isenabled()


def test_pause_leaves_a_disabled_collector_disabled() -> None:
    gc.disable()
    try:
        with collector.paused():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_cyclic_garbage_made_in_a_pause_is_still_collected() -> None:
    # What a pause built goes to the oldest generation, still tracked: a full collection
    # finds its cycles (nothing leaks through gc.freeze/unfreeze).
    with collector.paused():
        cycle = _Cycle()
        ref = weakref.ref(cycle)
        assert gc.is_tracked(cycle)
        del cycle
    assert ref() is not None  # a cycle: reference counting alone cannot free it
    gc.collect()
    assert ref() is None


def test_a_pickled_tree_is_equal_and_its_caches_start_empty() -> None:
    text = ("package p\npmodel M {\n\tlocal link L {\n\t\tdef { }\n"
            "\t\tlocal body B { def { box(length = 1, width = 1, height = 1) } }\n\t}\n}\n")
    tree = parse_text(text, "m.rsm").file
    assert tree is not None
    link = next(b for b in tree.items[1].members if isinstance(b, ast.Block))
    assert link.blocks  # fills the member-view cache of the link
    assert link._views is not None
    copy = pickle.loads(pickle.dumps(tree, protocol=pickle.HIGHEST_PROTOCOL))
    assert copy == tree and copy.span == tree.span
    copied_link = next(b for b in copy.items[1].members if isinstance(b, ast.Block))
    assert copied_link._views is None  # caches are not pickled, they are rebuilt
    assert copied_link.blocks == link.blocks and copied_link.blocks[0].span == link.blocks[0].span


def _passes_in_a_child(code: str) -> None:
    """``code`` run by a fresh interpreter (the collector's settings are per process), which
    ends by printing ``ok``."""
    out = subprocess.run([sys.executable, "-c", code + "print('ok')\n"], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0 and out.stdout == "ok\n", out.stderr


def test_a_command_keeps_what_a_pause_built_frozen() -> None:
    """In the ``cyphy`` command (cli.run calls keep_frozen), what a pause built stays out of
    every later collection: none of them traverses it again. A child process, as the flag
    is for the whole process."""
    code = (
        "import gc\n"
        "from cyphy import collector\n"
        "with collector.paused():\n"
        "    kept = [[i] for i in range(100_000)]\n"
        "assert gc.get_freeze_count() == 0, gc.get_freeze_count()\n"
        "collector.keep_frozen()\n"
        "with collector.paused():\n"
        "    more = [[i] for i in range(100_000)]\n"
        "assert gc.isenabled()\n"
        "assert gc.get_freeze_count() >= 200_000, gc.get_freeze_count()\n"
        "collector.keep_frozen(False)\n"  # handed back, and no longer kept
        "assert gc.get_freeze_count() == 0, gc.get_freeze_count()\n"
        "with collector.paused():\n"
        "    last = [[i] for i in range(100_000)]\n"
        "assert gc.get_freeze_count() == 0, gc.get_freeze_count()\n"
    )
    _passes_in_a_child(code)


def test_the_cyphy_command_leaves_the_checked_model_frozen() -> None:
    """``cyphy check`` as the executable runs it (``cli.run``): when it exits, the syntax tree
    and what the checks built are frozen (counted just before ``os._exit``)."""
    code = (
        "import gc, os, sys\n"
        "exit = os._exit\n"
        "def counted(status):\n"
        "    sys.stdout.write(f'{gc.get_freeze_count()} {status}\\n'); sys.stdout.flush()\n"
        "    exit(status)\n"
        "os._exit = counted\n"
        f"sys.argv = ['cyphy', 'check', '-q', {str(EXAMPLES / 'marxbot')!r}]\n"
        "from cyphy import cli\n"
        "cli.run()\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, env={**os.environ, "CYPHY_NO_CACHE": "1"})
    frozen, status = out.stdout.split()
    assert status == "0", out.stderr
    assert int(frozen) > 20_000, out.stdout  # the marXbot's trees and checks: ~10^5 objects


def test_the_language_server_collects_what_each_check_built() -> None:
    """``cyphy lsp`` is started by the command, which keeps frozen; the server runs for hours
    and must not: building it turns that off (a child process, as the flag is global)."""
    pytest.importorskip("pygls")
    code = (
        "import gc\n"
        "from cyphy import collector\n"
        "collector.keep_frozen()\n"
        "from cyphy.lsp.server import build\n"
        "build(())\n"
        "with collector.paused():\n"
        "    built = [[i] for i in range(100_000)]\n"
        "assert gc.get_freeze_count() == 0, gc.get_freeze_count()\n"
    )
    _passes_in_a_child(code)
