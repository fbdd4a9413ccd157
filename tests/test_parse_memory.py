"""What keeps a large model's syntax tree and its cached pickle small (issue 29, docs/limits.md
"Scale"): token texts are interned and line numbers shared, and a p-model's blocks are
pickled each as a pickle of its own, so that writing the parse cache does not need the
pickler's memo of the whole tree. The results are unchanged: equal trees, spans included."""

from __future__ import annotations

import pickle
import tracemalloc

from synthetic import tree_model
from test_parse_engines import canonical

from cyphy.lang.ast import Block, PoseField
from cyphy.lang.parser import parse_text
from cyphy.pickling import _separate


def _walk(node: object):
    stack = [node]
    while stack:
        x = stack.pop()
        yield x
        if isinstance(x, (tuple, list)):
            stack.extend(x)
        elif hasattr(x, "__dataclass_fields__"):
            stack.extend(getattr(x, f) for f in x.__dataclass_fields__)


def test_equal_token_texts_and_line_numbers_are_one_object_each():
    result = parse_text(tree_model(300, 3), "big.pm")
    assert result.file is not None
    fields = [n for n in _walk(result.file) if isinstance(n, PoseField)]
    assert len(fields) > 3000
    keys = {}
    for f in fields:  # `x` … `yaw`: six strings for thousands of fields
        keys.setdefault(f.key, set()).add(id(f.key))
    assert sorted(keys) == ["pitch", "roll", "x", "y", "yaw", "z"]
    assert all(len(ids) == 1 for ids in keys.values()), {k: len(v) for k, v in keys.items()}
    numbers = {}
    for f in fields:
        numbers.setdefault(f.value.text, set()).add(id(f.value.text))
    assert all(len(ids) == 1 for ids in numbers.values())
    # every span starting on one line (past the small ints CPython shares) holds one int
    lines: dict[int, set[int]] = {}
    for n in _walk(result.file):
        span = getattr(n, "span", None)
        if span is not None and span.line > 256:
            lines.setdefault(span.line, set()).add(id(span.line))
    assert len(lines) > 1000 and all(len(ids) == 1 for ids in lines.values())


def test_blocks_pickle_separately_and_unpickle_equal():
    result = parse_text(tree_model(200, 3), "big.pm")
    data = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
    again = pickle.loads(data)
    assert canonical(again) == canonical(result)  # spans included
    link = next(n for n in _walk(result.file) if isinstance(n, Block) and n.kind.value == "link"
                and any(isinstance(m, Block) for m in n.members))
    func, args = link.__reduce__()
    assert func is _separate and isinstance(args[0], bytes)
    assert canonical(func(*args)) == canonical(link)
    # its bodies, sensors and joints are in its own pickle, not pickles of their own
    assert b"_separate" not in args[0]


def test_writing_the_cache_does_not_hold_the_whole_tree_twice():
    """The pickler's memo of a whole tree (an entry and an argument tuple per node) was as
    large as the tree; with the blocks pickled separately, the memory the write takes beyond
    the tree is about the pickle's own bytes."""
    result = parse_text(tree_model(300, 3), "big.pm")
    tracemalloc.start()
    try:
        data = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 2.5 * len(data), (peak, len(data))


def test_writing_many_blocks_reports_how_far_it_has_gone():
    """The parse cache's write of a large tree moves the progress line: every
    ``REPORT_EVERY`` separate pickles, the count so far (the 90k-link tree's write stood still
    for tens of seconds). Nothing is reported outside :func:`reporting`."""
    from cyphy import pickling

    result = parse_text(tree_model(1200, 3), "big.pm")
    counts: list[int] = []
    with pickling.reporting(counts.append):
        data = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
    assert counts == [500, 1000]  # 1,200 links, each its own pickle
    pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
    assert counts == [500, 1000]
    assert canonical(pickle.loads(data)) == canonical(result)
