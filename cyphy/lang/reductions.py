"""The syntax tree built while Lark's LALR parser reduces, instead of from a Lark tree afterwards.

Building Lark's ``Tree`` objects, propagating their positions and walking them again with the
builder took more than half of a long file's parse (a 1,000-link model, the collector paused as
in a command: 2.6-3.6 s of CPU, of which Lark's lexer and LALR loop alone took 1.1 s; built
here, 2.0 s). Lark's ``transformer=`` would skip the trees but loses the positions: its rule
callbacks see only the kept children (no keywords, no braces), and positions are only
propagated onto ``Tree`` results. So each grammar rule gets a callback of its own here, which
receives the reduced symbols as they are on the parser's stack, does what Lark's tree builder
(``maybe_placeholders``, ``?rule``, ``_rule`` inlining, ``propagate_positions``) would have
done with them, and calls the builder's method at once:

* every value on the stack is a lexer ``Token`` or a pair ``(value, position)``, ``position``
  being ``(line, column, end_line, end_column)`` or None for a rule that matched no text;
* a rule's position runs from the first positioned symbol it reduced to the last one,
  keywords and punctuation included (Lark's *container* position);
* anonymous tokens are dropped unless the rule keeps them (``!rule``), ``[x]`` leaves a None
  where ``x`` is absent, and an inlined ``_rule`` puts its children in its parent's place;
* a ``?rule`` with one child is that child, its position widened to what the rule reduced
  (``(x)`` makes ``x``'s parent start at the parenthesis, while ``x`` keeps its own span).

One divergence from Lark's trees cannot arise with this grammar: Lark fills in the position
of an *empty* rule that a ``?rule`` passes through from the surrounding symbols, after the
fact; here the empty rule's node is already built. No ``?rule`` of ``robosim.lark`` passes a
rule that can match nothing (``tests/test_parse_constructs.py`` checks the grammar for it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Iterable

from lark import Lark

from cyphy.lang.grammar import TOKEN_TYPES

#: ``(line, column, end_line, end_column)`` of a rule's text, or None when it matched nothing.
Pos = tuple[int, int, int, int] | None
Callback = Callable[[list[Any]], Any]


@dataclass(frozen=True, slots=True)
class Shape:
    """What one grammar rule (one alternative) keeps of the symbols it reduces."""

    method: str | None  # the builder's method, or None for an inlined ``_rule``
    include: tuple[tuple[int, bool, int], ...]  # (symbol index, splice it?, Nones before it)
    nones_after: int
    expand1: bool
    size: int  # symbols reduced
    #: whether the first and the last symbol reduced are terminals: a lexer token, whose
    #: position is the rule's start (end), with no search for the first positioned symbol
    starts_with_token: bool = False
    ends_with_token: bool = False


def shapes(parser: Lark) -> dict[Any, Shape]:
    """The shape of every rule of ``parser``, keyed by Lark's rule objects."""
    placeholders = parser.options.maybe_placeholders
    out: dict[Any, Shape] = {}
    for rule in parser.rules:
        options = rule.options
        empty = options.empty_indices if placeholders else ()
        if empty:  # Nones to insert before each kept symbol and after the last
            runs = [len(ones) for ones in "".join(str(int(b)) for b in empty).split("0")]
        else:
            runs = [0] * (len(rule.expansion) + 1)
        include = []
        pending = 0
        for i, sym in enumerate(rule.expansion):
            pending += runs[i]
            if options.keep_all_tokens or not (sym.is_term and sym.filter_out):
                include.append((i, not sym.is_term and sym.name.startswith("_"), pending))
                pending = 0
        name = rule.alias or options.template_source or rule.origin.name
        inlined = name.startswith("_")
        expansion = rule.expansion
        out[rule] = Shape(None if inlined else name, tuple(include), pending + runs[-1],
                          bool(options.expand1 and not rule.alias and not inlined),
                          len(expansion), bool(expansion) and expansion[0].is_term,
                          bool(expansion) and expansion[-1].is_term)
    return out


def callbacks(rule_shapes: dict[Any, Shape], builder: object) -> dict[Any, Callback]:
    """One callback per rule, calling ``builder``'s methods (``method(pos, children)``). A
    ``?rule`` alternative with a single child needs no method (it never makes a node)."""
    return {rule: _callback(shape, _method(builder, shape)) for rule, shape in rule_shapes.items()}


def _method(builder: object, shape: Shape) -> Callable[[Pos, list[Any]], Any] | None:
    if shape.method is None:
        return None
    children = sum(1 + nones for _, _, nones in shape.include) + shape.nones_after
    if shape.expand1 and children == 1 and not any(splice for _, splice, _ in shape.include):
        return getattr(builder, shape.method, None)
    return getattr(builder, shape.method)  # a rule without its method is a builder bug


def _callback(shape: Shape, method: Callable[[Pos, list[Any]], Any] | None) -> Callback:
    include, nones_after, expand1 = shape.include, shape.nones_after, shape.expand1
    if expand1 and include == ((0, False, 0),) and not nones_after and shape.size == 1:
        return _first  # `?postfix: atom`: the child, its position unchanged

    simple = nones_after == 0 and all(not splice and not nones for _, splice, nones in include)
    indices = tuple(i for i, _, _ in include)
    position = _positioner(shape)
    if simple and len(indices) == 1 and not expand1:
        return _one_child(indices[0], position, method)
    if simple and len(indices) == 2 and not expand1 and method is not None:
        return _two_children(indices, position, method)
    if method is None and not expand1 and not nones_after:
        if include == ((0, True, 0),):
            return _spliced(position)
        if len(include) == 2 and include[0] == (0, True, 0) and include[1][2] == 0:
            return _grown(include[1][0], include[1][1], position)

    def reduce(symbols: list[Any]) -> Any:
        pos = position(symbols)
        if simple:
            children = [s if type(s) is not tuple else s[0]
                        for i in indices for s in (symbols[i],)]
        else:
            children = []
            for i, splice, nones in include:
                if nones:
                    children += [None] * nones
                s = symbols[i]
                if not splice:
                    children.append(s if type(s) is not tuple else s[0])
                elif children:
                    children += s[0]
                else:  # a list grown one member at a time (`_member*`) is extended in place,
                    children = s[0]  # not copied: each reduced value has one consumer
            if nones_after:
                children += [None] * nones_after
        if expand1 and len(children) == 1:
            only = children[0]
            # A lone token is passed on as it is (Lark does not move a token's position).
            return only if isinstance(only, TOKEN_TYPES) else (only, pos)
        if method is None:
            return (children, pos)
        return (method(pos, children), pos)

    return reduce


def _first(symbols: list[Any]) -> Any:
    return symbols[0]


def _one_child(index: int, position: Callable[[list[Any]], Pos],
               method: Callable[[Pos, list[Any]], Any] | None) -> Callback:
    """``reduce`` for the commonest shape, a rule that keeps one symbol: it makes a node
    (``atom: NUMBER``, ``expr: unit``) or starts a list (``_member*``'s first member). The
    same result as ``reduce``'s, with less work per reduction."""
    if method is None:
        def first_member(symbols: list[Any]) -> Any:
            s = symbols[index]
            return ([s if type(s) is not tuple else s[0]], position(symbols))
        return first_member

    def reduce_one(symbols: list[Any]) -> Any:
        pos = position(symbols)
        s = symbols[index]
        return (method(pos, [s if type(s) is not tuple else s[0]]), pos)

    return reduce_one


def _two_children(indices: tuple[int, ...], position: Callable[[list[Any]], Pos],
                  method: Callable[[Pos, list[Any]], Any]) -> Callback:
    """``reduce`` for a rule that keeps two symbols and makes a node (``pose_field: NAME
    "=" expr``)."""
    first, second = indices

    def reduce_two(symbols: list[Any]) -> Any:
        pos = position(symbols)
        a, b = symbols[first], symbols[second]
        return (method(pos, [a if type(a) is not tuple else a[0],
                             b if type(b) is not tuple else b[0]]), pos)

    return reduce_two


def _spliced(position: Callable[[list[Any]], Pos]) -> Callback:
    """``reduce`` for an inlined rule that is one inlined rule (``_member*``'s first member,
    a ``_member``): its children, the same list, as ``reduce`` passes them on."""

    def splice(symbols: list[Any]) -> Any:
        return (symbols[0][0], position(symbols))

    return splice


def _grown(index: int, spliced: bool, position: Callable[[list[Any]], Pos]) -> Callback:
    """``reduce`` for a list that grows by one member, or by an inlined rule's children
    (``_member*``'s ``list _member``): the list is extended in place, as ``reduce`` does."""
    if spliced:
        def grow_by(symbols: list[Any]) -> Any:
            members = symbols[0][0]
            members += symbols[index][0]
            return (members, position(symbols))
        return grow_by

    def grow(symbols: list[Any]) -> Any:
        members = symbols[0][0]
        s = symbols[index]
        members.append(s if type(s) is not tuple else s[0])
        return (members, position(symbols))

    return grow


def _positioner(shape: Shape) -> Callable[[list[Any]], Pos]:
    """:func:`_position` for one rule: a rule that starts or ends with a token (a keyword,
    a brace) takes that token's start or end, the rule's first or last positioned symbol."""
    if shape.size == 1:  # the one symbol's position: no end to search for
        return _first_position
    if shape.starts_with_token and shape.ends_with_token:
        def both(symbols: list[Any]) -> Pos:
            first, last = symbols[0], symbols[-1]
            return (first.line, first.column, last.end_line, last.end_column)
        return both
    if shape.starts_with_token:
        def start(symbols: list[Any]) -> Pos:
            first = symbols[0]
            end = _first_position(reversed(symbols))
            assert end is not None  # the first symbol is positioned
            return (first.line, first.column, end[2], end[3])
        return start
    if shape.ends_with_token:
        def end(symbols: list[Any]) -> Pos:
            start = _first_position(symbols)
            assert start is not None  # the last symbol is positioned
            last = symbols[-1]
            return (start[0], start[1], last.end_line, last.end_column)
        return end
    return _position


def _position(symbols: list[Any]) -> Pos:
    """From the first positioned symbol's start to the last one's end."""
    start = _first_position(symbols)
    if start is None:
        return None
    end = _first_position(reversed(symbols))
    assert end is not None
    return (start[0], start[1], end[2], end[3])


def _first_position(symbols: Iterable[Any]) -> Pos:
    for s in symbols:
        if type(s) is not tuple:
            return (s.line, s.column, s.end_line, s.end_column)  # a token
        if s[1] is not None:
            return s[1]
    return None
