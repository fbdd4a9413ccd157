"""The collector pause (cyphy/collector.py) and the fast pickling of syntax trees
(cyphy/pickling.py): what they promise besides speed."""

from __future__ import annotations

import gc
import pickle
import weakref

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
