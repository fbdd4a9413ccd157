"""Text → syntax tree. The only module that touches Lark.

The grammar (``robosim.lark``) is loaded once. Parse errors become diagnostics with spans and
hints; the transformer turns Lark trees into the frozen dataclasses of :mod:`cyphy.lang.ast` and
:mod:`cyphy.expr`, so no Lark object leaves this module.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Iterable

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from cyphy import codes, progress
from cyphy import expr as ex
from cyphy.diagnostics import Diagnostic, Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.ast import ParseResult

GRAMMAR = "robosim.lark"
POSE_KEYS = ("x", "y", "z", "roll", "pitch", "yaw")


@lru_cache(maxsize=None)
def grammar(strict: bool = False) -> Lark:
    """The LALR parser with the contextual lexer, built once per process."""
    return Lark.open_from_package(
        "cyphy.lang",
        GRAMMAR,
        parser="lalr",
        lexer="contextual",
        propagate_positions=True,
        maybe_placeholders=True,
        strict=strict,
        # Lark stores the LALR tables in a temporary file keyed by the grammar's hash: the
        # analysis takes 0.7 s, loading the cache a few milliseconds.
        cache=not strict,
        lexer_callbacks={"LBRACE": _reached},  # progress through a long file, block by block
    )


def _reached(token: Token) -> Token:
    progress.step(f"line {token.line}")
    return token


def parse_text(text: str, path: str = "<string>") -> ParseResult:
    """Parse one file's text. Never raises for bad input: problems come back as diagnostics."""
    if text.startswith("\ufeff"):
        text = text[1:]
    try:
        tree = grammar().parse(text)
    except UnexpectedInput as err:
        return ParseResult(None, (_syntax_diagnostic(err, text, path),))
    builder = _Builder(text, path)
    progress.step("building the syntax tree")
    result = builder.transform(tree)
    return ParseResult(result, tuple(builder.diagnostics))


# --------------------------------------------------------------------------- parse errors

_FRIENDLY = {
    "NAME": "a name",
    "NUMBER": "a number",
    "STRING": "a string",
    "UNIT": "a unit",
    "$END": "end of file",
}


def _describe_terminal(name: str) -> str:
    if name in _FRIENDLY:
        return _FRIENDLY[name]
    try:
        term = grammar().get_terminal(name)
    except KeyError:
        return name
    if term.pattern.type == "str":
        return f"'{term.pattern.value}'"
    return name.lower()


def _expected_text(expected: Iterable[str]) -> str:
    names = sorted({_describe_terminal(e) for e in expected})
    if len(names) > 12:
        names = names[:12] + ["…"]
    return ", ".join(names)


def _keywords(expected: Iterable[str]) -> list[str]:
    out = []
    for e in expected:
        try:
            term = grammar().get_terminal(e)
        except KeyError:
            continue
        if term.pattern.type == "str" and term.pattern.value.isidentifier():
            out.append(term.pattern.value)
    return out


def _open_blocks(text: str, upto: int) -> list[int]:
    """Offsets of the braces still open at ``upto`` (ignoring comments and strings)."""
    stack: list[int] = []
    i = 0
    while i < upto:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = upto if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = upto if j < 0 else j + 2
            continue
        if c == '"':
            j = text.find('"', i + 1)
            i = upto if j < 0 else j + 1
            continue
        if c == "{":
            stack.append(i)
        elif c == "}" and stack:
            stack.pop()
        i += 1
    return stack


def _line_col(text: str, offset: int) -> tuple[int, int]:
    line = text.count("\n", 0, offset) + 1
    col = offset - (text.rfind("\n", 0, offset) + 1) + 1
    return line, col


def _syntax_diagnostic(err: UnexpectedInput, text: str, path: str) -> Diagnostic:
    line = getattr(err, "line", 1) or 1
    column = getattr(err, "column", 1) or 1
    if isinstance(err, UnexpectedCharacters):
        char = text[err.pos_in_stream] if err.pos_in_stream < len(text) else ""
        hint = "remove the character or check the spelling around it"
        message = f"unexpected character {char!r}"
        if text.startswith("/*", err.pos_in_stream):
            message = "unterminated block comment"
            hint = "close the comment with '*/'"
        elif char == '"':
            message = "unterminated string"
            hint = "close the string with '\"'"
        elif char == "^":
            hint = "'^' is a power operator or escapes a name ('^x'); nothing else"
        elif err.allowed:
            hint = f"expected {_expected_text(err.allowed)}"
        span = Span(path, line, column, line, column + 1)
        return Diagnostic(codes.LEX, message, span, hint)

    if isinstance(err, (UnexpectedToken, UnexpectedEOF)):
        token = getattr(err, "token", None)
        expected = getattr(err, "expected", set()) or set()
        at_end = token is None or token.type == "$END"
        if at_end:
            opened = _open_blocks(text, len(text))
            if opened:
                oline, ocol = _line_col(text, opened[-1])
                span = Span(path, oline, ocol, oline, ocol + 1)
                return Diagnostic(
                    codes.SYNTAX,
                    "unexpected end of file: this block is not closed",
                    span,
                    "add the missing '}'",
                    (f"expected {_expected_text(expected)}",),
                )
            eline, ecol = _line_col(text, len(text))
            span = Span(path, eline, ecol, eline, ecol + 1)
            return Diagnostic(
                codes.SYNTAX,
                "unexpected end of file",
                span,
                f"expected {_expected_text(expected)}",
            )
        value = str(token)
        rest = text[token.start_pos:] if token.start_pos is not None else ""
        if rest.startswith("/*") and "*/" not in rest:
            return Diagnostic(codes.LEX, "unterminated block comment",
                              Span(path, line, column, line, column + 2),
                              "close the comment with '*/'")
        if rest.startswith('"') and token.type != "STRING":
            return Diagnostic(codes.LEX, "unterminated string",
                              Span(path, line, column, line, column + 1),
                              "close the string with '\"'")
        end_col = (token.end_column or column + len(value)) if token.end_line == line else column + 1
        span = Span(path, line, column, line, max(end_col, column + 1))
        message = f"unexpected {_describe_token(token)}"
        hint = f"expected {_expected_text(expected)}"
        close = difflib.get_close_matches(value, _keywords(expected), n=1, cutoff=0.7)
        word = _connective(value, text[:token.start_pos or 0])
        if word:  # `a and b`: RoboSim's connectives are symbols
            symbol = "/\\" if word == "and" else "\\/"
            hint = f"RoboSim writes '{word}' as '{symbol}', for example a {symbol} b ({hint})"
        elif close and token.type == "NAME":
            hint = f"did you mean '{close[0]}'? ({hint})"
        elif token.type == "NAME" and value in _keywords(expected):
            pass
        return Diagnostic(codes.SYNTAX, message, span, hint)

    span = Span(path, line, column, line, column + 1)
    return Diagnostic(codes.SYNTAX, str(err).splitlines()[0], span, "")


def _connective(value: str, before: str) -> str | None:
    """``and`` or ``or`` when the unexpected token is that word or follows it: a newcomer's
    conjunction, which RoboSim writes ``/\\`` (and disjunction ``\\/``)."""
    if value in ("and", "or"):
        return value
    # `a and b`, or `(a) and (b)`, which parses as a call of `and` until the next line
    recent = "\n".join(before.splitlines()[-2:])
    found = re.findall(r"(?<![\w.:])(and|or)(?=\s*(?:\(|$))", recent)
    return found[-1] if found else None


def _describe_token(token: Token) -> str:
    if token.type == "NAME":
        return f"name '{token}'"
    if token.type == "NUMBER":
        return f"number {token}"
    return f"'{token}'"


# --------------------------------------------------------------------------- tree → AST


@dataclass(frozen=True, slots=True)
class _QN:
    parts: tuple[str, ...]
    span: Span


@dataclass(frozen=True, slots=True)
class _Tagged:
    """A child that only its parent interprets (index bracket, pre/postcondition…)."""

    tag: str
    value: Any
    span: Span


def _name(tok: Token) -> str:
    s = str(tok)
    return s[1:] if s.startswith("^") else s


def _unescape(s: str) -> str:
    body = s[1:-1]
    return body.replace('\\"', '"').replace("\\\\", "\\")


class _Builder:
    """Builds the AST bottom-up. Methods are named after grammar rules and aliases and take
    ``(meta, children)``. The walk is a loop over Lark's bottom-up subtree order, so a long
    expression does not exhaust Python's stack, and it skips the per-call wrappers of Lark's
    ``Transformer`` (a fifth of the parse time)."""

    def __init__(self, text: str, path: str) -> None:
        self.text = text
        self.path = path
        self.diagnostics: list[Diagnostic] = []

    def transform(self, tree: Tree) -> Any:
        order: list[Tree] = []
        stack = [tree]
        while stack:  # parents before children; reversed, children before parents
            node = stack.pop()
            order.append(node)
            stack.extend(c for c in node.children if isinstance(c, Tree))
        results: dict[int, Any] = {}
        for sub in reversed(order):
            children = [results.pop(id(c)) if isinstance(c, Tree) else c for c in sub.children]
            results[id(sub)] = getattr(self, sub.data)(sub.meta, children)
        return results[id(tree)]

    # ----- helpers
    def _span(self, meta: Any) -> Span:
        if getattr(meta, "empty", True):
            return Span(self.path, 1, 1, 1, 1)
        return Span(self.path, meta.line, meta.column, meta.end_line, meta.end_column)

    def _tok_span(self, tok: Token) -> Span:
        return Span(self.path, tok.line or 0, tok.column or 0, tok.end_line or 0,
                    tok.end_column or 0)

    @staticmethod
    def _flat(children: Iterable[Any]) -> tuple[Any, ...]:
        out: list[Any] = []
        for c in children:
            if c is None:
                continue
            if isinstance(c, list):
                out.extend(c)
            else:
                out.append(c)
        return tuple(out)

    # ----- files
    def start(self, meta: Any, children: list[Any]) -> ast.SourceFile:
        return ast.SourceFile(self.path, self._flat(children), span=self._span(meta))

    def package_decl(self, meta: Any, c: list[Any]) -> ast.PackageDecl:
        return ast.PackageDecl(c[0].parts, span=self._span(meta))

    def endpackage(self, meta: Any, c: list[Any]) -> ast.EndPackage:
        return ast.EndPackage(span=self._span(meta))

    def import_all(self, meta: Any, c: list[Any]) -> ast.Import:
        return ast.Import(tuple(_name(t) for t in c), True, span=self._span(meta))

    def import_one(self, meta: Any, c: list[Any]) -> ast.Import:
        return ast.Import(tuple(_name(t) for t in c), False, span=self._span(meta))

    def qname(self, meta: Any, c: list[Token]) -> _QN:
        return _QN(tuple(_name(t) for t in c), self._span(meta))

    # ----- declarations
    def var_decl(self, meta: Any, c: list[Any]) -> _Tagged:
        name, type_, value = c
        return _Tagged(_name(name), (type_, value), self._span(meta))

    def _decls(self, kind: ast.DeclKind, c: list[_Tagged]) -> list[ast.VarDecl]:
        return [ast.VarDecl(kind, t.tag, t.value[0], t.value[1], span=t.span) for t in c]

    def const_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.CONST, c)

    def var_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.VAR, c)

    def input_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.INPUT, c)

    def output_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.OUTPUT, c)

    def inout_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.INOUT, c)

    def local_decls(self, meta: Any, c: list[Any]) -> list[ast.VarDecl]:
        return self._decls(ast.DeclKind.LOCAL, c)

    def prim_type(self, meta: Any, c: list[Token]) -> ast.PrimitiveType:
        return ast.PrimitiveType(str(c[0]), span=self._span(meta))

    def vector_type(self, meta: Any, c: list[Any]) -> ast.VectorType:
        return ast.VectorType(c[0], c[1], span=self._span(meta))

    def matrix_type(self, meta: Any, c: list[Any]) -> ast.MatrixType:
        return ast.MatrixType(c[0], c[1], c[2], span=self._span(meta))

    def seq_type(self, meta: Any, c: list[Any]) -> ast.SeqType:
        return ast.SeqType(c[0], span=self._span(meta))

    def set_type(self, meta: Any, c: list[Any]) -> ast.SetType:
        return ast.SetType(c[0], span=self._span(meta))

    def named_type(self, meta: Any, c: list[Any]) -> ast.NamedType:
        return ast.NamedType(c[0].parts, span=self._span(meta))

    def type_decl(self, meta: Any, c: list[Token]) -> ast.TypeDecl:
        return ast.TypeDecl(_name(c[0]), span=self._span(meta))

    def param(self, meta: Any, c: list[Any]) -> ast.Param:
        return ast.Param(_name(c[0]), c[1], span=self._span(meta))

    field = param

    def function_decl(self, meta: Any, c: list[Any]) -> ast.FunctionDecl:
        name, rest = c[0], self._flat(c[1:])
        params = tuple(x for x in rest if isinstance(x, ast.Param))
        types = [x for x in rest if not isinstance(x, (ast.Param, _Tagged))]
        body = [x for x in rest if isinstance(x, _Tagged)]
        conditions = body[0].value if body else []
        return ast.FunctionDecl(
            _name(name),
            params,
            types[0] if types else None,
            tuple(v for k, v in conditions if k == "pre"),
            tuple(v for k, v in conditions if k == "post"),
            span=self._span(meta),
        )

    def function_body(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("body", list(c), self._span(meta))

    def precondition(self, meta: Any, c: list[Any]) -> tuple[str, ex.Expr]:
        return ("pre", c[0])

    def postcondition(self, meta: Any, c: list[Any]) -> tuple[str, ex.Expr]:
        return ("post", c[0])

    def datatype(self, meta: Any, c: list[Any]) -> ast.DataType:
        return ast.DataType(_name(c[0]), tuple(c[1:]), False, span=self._span(meta))

    def record(self, meta: Any, c: list[Any]) -> ast.DataType:
        return ast.DataType(_name(c[0]), tuple(c[1:]), True, span=self._span(meta))

    def enumeration(self, meta: Any, c: list[Token]) -> ast.Enumeration:
        return ast.Enumeration(_name(c[0]), tuple(_name(t) for t in c[1:]), span=self._span(meta))

    def primitive_unit(self, meta: Any, c: list[Token]) -> ast.UnitDecl:
        return ast.UnitDecl(_name(c[0]), span=self._span(meta))

    def derived_unit(self, meta: Any, c: list[Any]) -> ast.UnitDecl:
        return ast.UnitDecl(_name(c[0]), c[1], c[2], span=self._span(meta))

    # ----- annotations
    def annotation_template(self, meta: Any, c: list[Any]) -> ast.AnnotationTemplate:
        name, extends, *params = c
        return ast.AnnotationTemplate(
            _name(name), extends.parts if extends else None, tuple(params), span=self._span(meta)
        )

    def value_param(self, meta: Any, c: list[Any]) -> ast.TemplateParam:
        # `["=" _ann_value]` inlines its rule, so an absent default leaves no placeholder.
        name, type_, *rest = c
        default = rest[0] if rest else None
        return ast.TemplateParam(_name(name), type_, None, default, span=self._span(meta))

    def template_param(self, meta: Any, c: list[Any]) -> ast.TemplateParam:
        name, template, default = c
        return ast.TemplateParam(_name(name), None, template.parts, default, span=self._span(meta))

    def annotation(self, meta: Any, c: list[Any]) -> ast.Annotation:
        span = self._span(meta)
        inst = ast.TemplateInstance(c[0].parts, tuple(c[1:]), span=span)
        return ast.Annotation(inst, span=span)

    def ann_inst(self, meta: Any, c: list[Any]) -> ast.AnnotationArg:
        return ast.AnnotationArg(_name(c[0]), c[1], span=self._span(meta))

    def template_inst(self, meta: Any, c: list[Any]) -> ast.TemplateInstance:
        return ast.TemplateInstance(c[0].parts, tuple(c[1:]), span=self._span(meta))

    # ----- p-models and blocks
    def pmodel(self, meta: Any, c: list[Any]) -> ast.PModel:
        return ast.PModel(_name(c[0]), self._flat(c[1:]), False, span=self._span(meta))

    def fragment(self, meta: Any, c: list[Any]) -> ast.PModel:
        return ast.PModel(_name(c[0]), self._flat(c[1:]), True, span=self._span(meta))

    def block_kind(self, meta: Any, c: list[Token]) -> ast.BlockKind:
        return ast.BlockKind(str(c[0]))

    def ref_kind(self, meta: Any, c: list[Token]) -> ast.BlockKind:
        return ast.REF_KINDS[str(c[0])]

    def definition(self, meta: Any, c: list[Any]) -> ast.Definition:
        return ast.Definition(c[0], _name(c[1]), self._flat(c[2:]), span=self._span(meta))

    def local_block(self, meta: Any, c: list[Any]) -> ast.Block:
        return ast.Block(c[0], _name(c[1]), None, self._flat(c[2:]), span=self._span(meta))

    def ref_block(self, meta: Any, c: list[Any]) -> ast.Block:
        kind, name, target, *members = c
        return ast.Block(kind, _name(name), target.parts, self._flat(members),
                         span=self._span(meta))

    def def_block(self, meta: Any, c: list[Any]) -> ast.DefBlock:
        return ast.DefBlock(self._flat(c), span=self._span(meta))

    def equation(self, meta: Any, c: list[Any]) -> ast.Equation:
        return ast.Equation(c[0], span=self._span(meta))

    def constraint(self, meta: Any, c: list[Any]) -> ast.Constraint:
        return ast.Constraint(c[0], span=self._span(meta))

    def relation(self, meta: Any, c: list[Any]) -> ast.Relation:
        return ast.Relation(c[0], span=self._span(meta))

    def relation_flexi(self, meta: Any, c: list[Any]) -> ast.Relation:
        return ast.Relation(c[0], flexi=True, span=self._span(meta))

    def bare_relation(self, meta: Any, c: list[Any]) -> ast.Relation:
        span = self._span(meta)
        return ast.Relation(ex.BinOp(c[1], c[0], c[2], span=span), bare=True, span=span)

    def instantiation(self, meta: Any, c: list[Any]) -> ast.Instantiation:
        return ast.Instantiation(_name(c[0]), c[1], span=self._span(meta))

    def fixed(self, meta: Any, c: list[Any]) -> ast.FixedConnection:
        return ast.FixedConnection(_name(c[0]), _name(c[1]) if c[1] else None,
                                   span=self._span(meta))

    def flexible(self, meta: Any, c: list[Any]) -> ast.FlexibleConnection:
        return ast.FlexibleConnection(_name(c[0]), _name(c[1]) if c[1] else None,
                                      span=self._span(meta))

    def part(self, meta: Any, c: list[Any]) -> ast.Part:
        name, target, *members = c
        return ast.Part(_name(name), target.parts, self._flat(members), span=self._span(meta))

    def part_fixed(self, meta: Any, c: list[Any]) -> ast.PartFixed:
        return ast.PartFixed(_name(c[0]), _name(c[1]), _name(c[2]) if c[2] else None,
                             span=self._span(meta))

    def part_flexible(self, meta: Any, c: list[Any]) -> ast.PartFlexible:
        return ast.PartFlexible(_name(c[0]), _name(c[1]), _name(c[2]) if c[2] else None,
                                span=self._span(meta))

    def pose(self, meta: Any, c: list[Any]) -> ast.Pose:
        return ast.Pose(tuple(c), span=self._span(meta))

    def pose_field(self, meta: Any, c: list[Any]) -> ast.PoseField:
        key, span = _name(c[0]), self._span(meta)
        if key not in POSE_KEYS:
            self.diagnostics.append(Diagnostic(
                codes.MEMBER, f"a pose has no field '{key}'", self._tok_span(c[0]),
                (did_you_mean(key, POSE_KEYS) + " ").lstrip()
                + "the fields are " + ", ".join(POSE_KEYS)))
        return ast.PoseField(key, c[1], span=span)

    def index(self, meta: Any, c: list[Any]) -> ast.IndexDecl:
        return ast.IndexDecl(_name(c[0]), c[1], c[2], c[3], span=self._span(meta))

    def half_open(self, meta: Any, c: list[Any]) -> bool:
        return False

    def closed(self, meta: Any, c: list[Any]) -> bool:
        return True

    # ----- body properties
    def shape_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def shape(self, meta: Any, c: list[Any]) -> ast.Shape:
        return ast.Shape(c[0], self._flat(c[1:]), span=self._span(meta))

    def geom_arg(self, meta: Any, c: list[Any]) -> ast.GeomArg:
        return ast.GeomArg(_name(c[0]), c[1], span=self._span(meta))

    def mesh_shape(self, meta: Any, c: list[Token]) -> _Tagged:
        return _Tagged("shape", _unescape(str(c[0])), self._span(meta))

    def mesh_scaling(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("scaling", c[0], self._span(meta))

    def mesh(self, meta: Any, c: list[_Tagged]) -> ast.Mesh:
        span = self._span(meta)
        values: dict[str, Any] = {}
        for t in c:
            if t.tag in values:
                self._duplicate(t.tag, "mesh", t.span)
            values.setdefault(t.tag, t.value)
        return ast.Mesh(values.get("shape"), values.get("scaling"), span=span)

    def mass(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("mass", c[0], self._span(meta))

    def inertia_matrix(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("inertia", tuple(c), self._span(meta))

    def inertia_entry(self, meta: Any, c: list[Any]) -> ast.InertiaEntry:
        return ast.InertiaEntry(_name(c[0]), c[1], span=self._span(meta))

    def inertial(self, meta: Any, c: list[Any]) -> ast.Inertial:
        values: dict[str, Any] = {}
        order = []
        for item in c:
            tag, value, span = (("pose", item, item.span) if isinstance(item, ast.Pose)
                                else (item.tag, item.value, item.span))
            if tag in values:
                self._duplicate(tag, "inertial information", span)
            values.setdefault(tag, value)
            order.append(tag)
        return ast.Inertial(values.get("mass"), values.get("inertia"), values.get("pose"),
                            tuple(order), span=self._span(meta))

    def restitution(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("restitution", c[0], self._span(meta))

    def threshold(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("threshold", c[0], self._span(meta))

    def bounce(self, meta: Any, c: list[_Tagged]) -> ast.Bounce:
        values = {t.tag: t.value for t in c}
        return ast.Bounce(values.get("restitution"), values.get("threshold"),
                          span=self._span(meta))

    def friction_entry(self, meta: Any, c: list[Any]) -> ast.FrictionEntry:
        return ast.FrictionEntry(_name(c[0]), c[1], span=self._span(meta))

    def friction(self, meta: Any, c: list[Any]) -> ast.Friction:
        return ast.Friction(tuple(c), span=self._span(meta))

    def laser_retro(self, meta: Any, c: list[Any]) -> ast.LaserRetro:
        return ast.LaserRetro(c[0], span=self._span(meta))

    def _duplicate(self, what: str, where: str, span: Span) -> None:
        self.diagnostics.append(
            Diagnostic(codes.DUPLICATE_MEMBER, f"'{what}' is given twice in {where}", span,
                       f"keep one '{what}'")
        )

    # ----- solutions
    def solution(self, meta: Any, c: list[Any]) -> ast.Solution:
        name, type_, order, group, method, *rest = c
        return ast.Solution(
            _name(name), type_, int(str(order).split(".")[0]), int(str(group).split(".")[0]),
            _name(method),
            tuple(x for x in rest if isinstance(x, ast.SolutionInput)),
            tuple(x for x in rest if isinstance(x, ast.Constraint)),
            span=self._span(meta),
        )

    def solution_input(self, meta: Any, c: list[Any]) -> ast.SolutionInput:
        return ast.SolutionInput(_name(c[0]), c[1], span=self._span(meta))

    # ----- mappings
    def platform_mapping(self, meta: Any, c: list[Any]) -> ast.PlatformMapping:
        name, dmodel, pmodel, *members = c
        return ast.PlatformMapping(
            _name(name), dmodel.parts, pmodel.parts, self._flat(members),
            span=self._span(meta), dmodel_span=dmodel.span, pmodel_span=pmodel.span,
        )

    def operation_mapping(self, meta: Any, c: list[Any]) -> ast.OperationMapping:
        return ast.OperationMapping(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def _event_mapping(self, direction: str, meta: Any, c: list[Any]) -> ast.EventMapping:
        name, param, *members = c
        return ast.EventMapping(
            direction, _name(name), param.value if param else None, self._flat(members),
            span=self._span(meta), param_span=param.span if param else None,
        )

    def input_event_mapping(self, meta: Any, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("input", meta, c)

    def output_event_mapping(self, meta: Any, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("output", meta, c)

    def variable_mapping(self, meta: Any, c: list[Any]) -> ast.VariableMapping:
        return ast.VariableMapping(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def event_param(self, meta: Any, c: list[Token]) -> _Tagged:
        return _Tagged("param", _name(c[0]), self._span(meta))

    def predicate(self, meta: Any, c: list[Any]) -> ast.Predicate:
        return ast.Predicate(c[0], span=self._span(meta))

    def action(self, meta: Any, c: list[Any]) -> ast.Action:
        return ast.Action(c[0], span=self._span(meta))

    def statement(self, meta: Any, c: list[Any]) -> tuple[ast.Statement, ...]:
        return tuple(c)

    def assignment(self, meta: Any, c: list[Any]) -> ast.Assign:
        return ast.Assign(c[0], c[1], span=self._span(meta))

    def call_statement(self, meta: Any, c: list[Any]) -> ast.Statement:
        call, span = c[0], self._span(meta)
        if (isinstance(call, ex.Call) and isinstance(call.func, ex.Name)
                and call.func.parts == ("wait",) and len(call.args) == 1):
            return ast.WaitStatement(call.args[0], span=span)
        return ast.CallStatement(call, span=span)

    def skip_statement(self, meta: Any, c: list[Any]) -> ast.SkipStatement:
        return ast.SkipStatement(span=self._span(meta))

    # ----- d-models
    def interface(self, meta: Any, c: list[Any]) -> ast.Interface:
        return ast.Interface(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def event_decl(self, meta: Any, c: list[Any]) -> ast.EventDecl:
        return ast.EventDecl(_name(c[0]), c[1], span=self._span(meta))

    def operation_sig(self, meta: Any, c: list[Any]) -> ast.OperationSig:
        return ast.OperationSig(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def clock_decl(self, meta: Any, c: list[Token]) -> ast.ClockDecl:
        return ast.ClockDecl(_name(c[0]), span=self._span(meta))

    def robotic_platform(self, meta: Any, c: list[Any]) -> ast.RoboticPlatform:
        return ast.RoboticPlatform(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def uses(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("uses", c[0].parts, span=self._span(meta))

    def provides(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("provides", c[0].parts, span=self._span(meta))

    def requires(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("requires", c[0].parts, span=self._span(meta))

    def module(self, meta: Any, c: list[Any]) -> ast.Module:
        return ast.Module(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def cycle_def(self, meta: Any, c: list[Any]) -> ast.CycleDef:
        return ast.CycleDef(c[0], span=self._span(meta))

    def node_ref_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def node_ref(self, meta: Any, c: list[Any]) -> ast.NodeRef:
        return ast.NodeRef(c[0], _name(c[1]), c[2].parts, span=self._span(meta))

    def connection(self, meta: Any, c: list[Any]) -> ast.Connection:
        a, ae, b, be, flag = c
        return ast.Connection(_name(a), _name(ae), _name(b), _name(be), flag,
                              span=self._span(meta))

    def connection_flag(self, meta: Any, c: list[Token]) -> str:
        return _name(c[0])

    # ----- behaviour: controllers, state machines, operation definitions
    def controller(self, meta: Any, c: list[Any]) -> ast.Controller:
        return ast.Controller(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def machine_ref_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def machine_ref(self, meta: Any, c: list[Any]) -> ast.MachineRef:
        return ast.MachineRef(c[0], _name(c[1]), c[2].parts, span=self._span(meta))

    def state_machine(self, meta: Any, c: list[Any]) -> ast.StateMachine:
        return ast.StateMachine(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def operation_def(self, meta: Any, c: list[Any]) -> ast.StateMachine:
        name, *rest = c
        params = tuple(x for x in rest if isinstance(x, ast.Param))
        members = self._flat(x for x in rest if not isinstance(x, ast.Param))
        return ast.StateMachine(_name(name), members, "operation", params,
                                span=self._span(meta))

    def terminates(self, meta: Any, c: list[Any]) -> ast.Terminates:
        return ast.Terminates(span=self._span(meta))

    def context_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def context(self, meta: Any, c: list[Any]) -> ast.Context:
        return ast.Context(c[0], tuple(c[1:]), span=self._span(meta))

    def _machine_node(self, kind: str, meta: Any, c: list[Token]) -> ast.MachineNode:
        return ast.MachineNode(kind, _name(c[0]), span=self._span(meta))

    def initial_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("initial", meta, c)

    def junction_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("junction", meta, c)

    def final_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("final", meta, c)

    def state(self, meta: Any, c: list[Any]) -> ast.State:
        return ast.State(_name(c[0]), self._flat(c[1:]), span=self._span(meta))

    def action_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def state_action(self, meta: Any, c: list[Any]) -> ast.StateAction:
        return ast.StateAction(c[0], c[1], span=self._span(meta))

    def transition_from(self, meta: Any, c: list[Token]) -> _Tagged:
        return _Tagged("from", _name(c[0]), self._tok_span(c[0]))

    def transition_to(self, meta: Any, c: list[Token]) -> _Tagged:
        return _Tagged("to", _name(c[0]), self._tok_span(c[0]))

    def exec_trigger(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("exec", True, self._span(meta))

    def transition_trigger(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("trigger", c[0], self._span(meta))

    def transition_condition(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("condition", c[0], self._span(meta))

    def transition(self, meta: Any, c: list[Any]) -> ast.Transition:
        name, *members = c
        span = self._span(meta)
        where = f"transition {_name(name)}"
        parts: dict[str, Any] = {}
        for m in members:
            tag, value, mspan = ((m.tag, m.value, m.span) if isinstance(m, _Tagged)
                                 else ("action", m.statements, m.span))
            if tag in parts:
                self._duplicate(tag, where, mspan)
                continue
            parts[tag] = (value, mspan)
        value = {k: v for k, (v, _) in parts.items()}
        return ast.Transition(
            _name(name), value.get("from"), value.get("to"), bool(value.get("exec")),
            value.get("trigger"), value.get("condition"), value.get("action"), span=span,
            source_span=parts["from"][1] if "from" in parts else None,
            target_span=parts["to"][1] if "to" in parts else None)

    def send_statement(self, meta: Any, c: list[Any]) -> ast.SendStatement:
        span = self._span(meta)
        if not isinstance(c[0], ex.PlatformRef):
            self.diagnostics.append(Diagnostic(
                codes.SYNTAX, "only an output event of the platform can be sent with '!'", span,
                "write $event!value"))
        return ast.SendStatement(c[0], c[1], span=span)

    def clock_reset(self, meta: Any, c: list[Token]) -> ast.ClockReset:
        return ast.ClockReset(_name(c[0]), span=self._span(meta))

    def exec_statement(self, meta: Any, c: list[Any]) -> ast.ExecStatement:
        return ast.ExecStatement(span=self._span(meta))

    # ----- expressions
    def binop(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    sum_op = cmp_op = binop

    def prefix(self, meta: Any, c: list[Token]) -> _Tagged:
        return _Tagged("prefix", str(c[0]), self._tok_span(c[0]))

    def unit(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("unit", c, self._span(meta))

    def power_group(self, meta: Any, c: list[Any]) -> _Tagged:
        return _Tagged("power_group", c[-1], self._span(meta))

    def expr(self, meta: Any, c: list[Any]) -> ex.Expr:
        """Apply operator precedence to a flat row of operands and operators (Pratt)."""
        items: list[tuple[str, Any]] = []
        for child in c:
            if isinstance(child, str):
                items.append(("op", child))
            elif isinstance(child, _Tagged) and child.tag == "power_group":
                items.append(("op", "^"))
                items.append(("term", child.value))
            elif isinstance(child, _Tagged) and child.tag == "unit":
                for part in child.value:
                    if isinstance(part, _Tagged):
                        items.append(("prefix", part))
                    else:
                        items.append(("term", part))
            else:
                items.append(("term", child))
        return _Pratt(items, self.path).parse()

    sum = expr

    def call(self, meta: Any, c: list[Any]) -> ex.Expr:
        func, args = c[0], tuple(a for a in c[1:] if a is not None)
        span = self._span(meta)
        if isinstance(func, ex.Name) and func.parts == ("derivative",) and len(args) == 1:
            return ex.Derivative(args[0], span=span)
        if isinstance(func, ex.Name) and func.parts == ("integral",) and len(args) in (1, 3):
            lower, upper = (args[1], args[2]) if len(args) == 3 else (None, None)
            return ex.Integral(args[0], lower, upper, span=span)
        return ex.Call(func, args, span=span)

    def index_expr(self, meta: Any, c: list[Any]) -> ex.Index:
        return ex.Index(c[0], tuple(c[1:]), span=self._span(meta))

    def member(self, meta: Any, c: list[Any]) -> ex.Member:
        return ex.Member(c[0], _name(c[1]), span=self._span(meta))

    def number(self, meta: Any, c: list[Token]) -> ex.Num:
        return ex.Num(str(c[0]), span=self._span(meta))

    def quantity(self, meta: Any, c: list[Any]) -> ex.Quantity:
        value, unit = c
        span = self._span(meta)
        if isinstance(value, Token):
            value = ex.Num(str(value), span=self._tok_span(value))
        return ex.Quantity(value, str(unit), span=span)

    def platform_ref(self, meta: Any, c: list[Any]) -> ex.PlatformRef:
        return ex.PlatformRef(c[0].parts, _name(c[1]) if c[1] is not None else None,
                              span=self._span(meta))

    def string(self, meta: Any, c: list[Token]) -> ex.Str:
        return ex.Str(_unescape(str(c[0])), span=self._span(meta))

    def true_lit(self, meta: Any, c: list[Any]) -> ex.Bool:
        return ex.Bool(True, span=self._span(meta))

    def false_lit(self, meta: Any, c: list[Any]) -> ex.Bool:
        return ex.Bool(False, span=self._span(meta))

    def name_ref(self, meta: Any, c: list[_QN]) -> ex.Name:
        return ex.Name(c[0].parts, span=self._span(meta))

    def field_value(self, meta: Any, c: list[Any]) -> tuple[str, ex.Expr]:
        return (_name(c[0]), c[1])

    def record_lit(self, meta: Any, c: list[Any]) -> ex.Record:
        return ex.Record(c[0].parts, tuple(c[1:]), span=self._span(meta))

    def row(self, meta: Any, c: list[Any]) -> tuple[ex.Expr, ...]:
        return tuple(c)

    def tuple_lit(self, meta: Any, c: list[Any]) -> ex.Vector:
        return ex.Vector(tuple(c), span=self._span(meta))

    def matrix_lit(self, meta: Any, c: list[Any]) -> ex.Matrix:
        return ex.Matrix(tuple(c), span=self._span(meta))

    def seq_lit(self, meta: Any, c: list[Any]) -> ex.Seq:
        return ex.Seq(tuple(x for x in c if x is not None), span=self._span(meta))

    def if_expr(self, meta: Any, c: list[Any]) -> ex.IfExpr:
        return ex.IfExpr(c[0], c[1], c[2], span=self._span(meta))


# Binding powers, loosest first; right-associative operators parse their right side at their
# own level, left-associative ones one above.
_INFIX: dict[str, tuple[int, bool]] = {
    "<=>": (10, True), "=>": (10, True),
    "\\/": (20, False),
    "/\\": (30, False),
    "==": (50, False), "!=": (50, False), "<": (50, False), "<=": (50, False),
    ">": (50, False), ">=": (50, False),
    "+": (60, False), "-": (60, False), "cat": (60, False),
    "*": (70, False), "/": (70, False), "%": (70, False),
    "^": (90, True),
}
_PREFIX = {"not": 40, "-": 80}


class _Pratt:
    """Precedence climbing over ``(kind, value)`` items: ``term`` (an Expr), ``op`` (an infix
    operator) and ``prefix`` (a tagged ``-`` or ``not`` with its span)."""

    def __init__(self, items: list[tuple[str, Any]], path: str) -> None:
        self.items = items
        self.pos = 0
        self.path = path

    def parse(self, min_bp: int = 0) -> ex.Expr:
        prefixes = []
        while self.items[self.pos][0] == "prefix":
            prefixes.append(self.items[self.pos][1])
            self.pos += 1
        left: ex.Expr = self.items[self.pos][1]
        self.pos += 1
        # Innermost prefix first, each taking the operators that bind tighter than itself
        # (`not a == b` is `not (a == b)`, `-x^2` is `-(x^2)`); a loop, not recursion, so a
        # run of a thousand minus signs is fine.
        for prefix in reversed(prefixes):
            operand = self._infix(left, _PREFIX[prefix.value])
            left = ex.UnaryOp(prefix.value, operand, span=self._join(prefix.span, operand.span))
        return self._infix(left, min_bp)

    def _infix(self, left: ex.Expr, min_bp: int) -> ex.Expr:
        while self.pos < len(self.items):
            kind, op = self.items[self.pos]
            bp, right_assoc = _INFIX[op]
            if bp < min_bp:
                break
            self.pos += 1
            right = self.parse(bp if right_assoc else bp + 1)
            left = ex.BinOp(op, left, right, span=self._join(left.span, right.span))
        return left

    @staticmethod
    def _join(a: Span, b: Span) -> Span:
        return Span(a.file, a.line, a.column, b.end_line, b.end_column)


def contains_lark_objects(node: object) -> bool:
    """True when a Lark ``Tree`` or ``Token`` is reachable from ``node`` (a test helper that
    guards the rule that no Lark object leaves this module)."""
    seen: set[int] = set()
    stack = [node]
    while stack:
        x = stack.pop()
        if id(x) in seen:
            continue
        seen.add(id(x))
        if isinstance(x, (Tree, Token)):
            return True
        if isinstance(x, (tuple, list)):
            stack.extend(x)
        elif hasattr(x, "__dataclass_fields__"):
            stack.extend(getattr(x, f) for f in x.__dataclass_fields__)
    return False
