"""The CyPhyCircus abstract syntax: what the paper's semantic rules build and printers print.

Expressions and predicates are the shared expression AST (:mod:`cyphy.expr`), with
``Derivative`` for time derivatives; this module adds what CyPhyCircus has on top of them:
types, declarations, schemas, processes and actions, plus the two predicate forms that the
rules need and expressions lack (existential quantification over locals, and a conjunction
of equations). Every node is a frozen dataclass compared by value, so a printed program read
back by a parser can be compared with the original (the round-trip tests).

Names are already mangled (``LMotor_das``); each printer applies its own lexical rules on
top (Isabelle reserved words, ``\\_`` in LaTeX).
"""

from __future__ import annotations

from dataclasses import field, fields
from typing import Iterator, Union

from cyphy import expr as ex
from cyphy.records import record

# --------------------------------------------------------------------------- types


@record
class TBasic:
    """A basic type: ``real``, ``nat``, ``int``, ``bool`` or a given set such as ``RSName``."""

    name: str


@record
class TSeq:
    """``seq T``: vectors and matrices (a matrix is a sequence of rows). ``size``: the
    number of items where the declaration fixes it (``vector(real, 6)``), so that printers
    whose target has no vectors can split the value into components; it does not take part
    in equality (CyPhyCircus's ``seq`` has no length)."""

    of: "Type"
    size: int | None = field(default=None, compare=False)


@record
class TProduct:
    """``T1 × T2 × …``: the values an operation call carries."""

    items: tuple["Type", ...]


Type = Union[TBasic, TSeq, TProduct]
REAL, NAT, INT, BOOL = TBasic("real"), TBasic("nat"), TBasic("int"), TBasic("bool")

# --------------------------------------------------------------------------- predicates


@record
class Binding:
    """A typed name: a schema field, a quantified or a bound variable, a parameter."""

    name: str
    type: Type


@record
class Exists:
    """``∃ x1 : T1; … • P1 ∧ … ∧ Pn``; with no bound names, just the conjunction."""

    bound: tuple[Binding, ...]
    body: tuple[ex.Expr, ...]


Predicate = Union[ex.Expr, Exists]

# --------------------------------------------------------------------------- actions


@record
class Skip:
    pass


@record
class Stop:
    pass


@record
class Dot:
    """``c.e``: a value that selects the channel's component (the mapped name)."""

    value: ex.Expr


@record
class Out:
    """``c!e``."""

    value: ex.Expr


@record
class In:
    """``c?x``: binds ``x`` in the rest of the prefix."""

    name: str


Field = Union[Dot, Out, In]


@record
class Comm:
    """A communication ``channel.tag!v?x``: ``tag`` is the mapped name that selects one
    variant of a register channel (``registerRead.obstacle``), None for plain channels."""

    channel: str
    tag: str | None
    fields: tuple[Field, ...]


@record
class Prefix:
    comm: Comm
    then: "Action"


@record
class Seq:
    """``A1 ; A2 ; …`` (two or more)."""

    items: tuple["Action", ...]


@record
class ExtChoice:
    items: tuple["Action", ...]


@record
class IndexedExtChoice:
    """``□ v : {v : T | P} • A``: one branch per value of ``v`` satisfying ``where``."""

    var: Binding
    where: Predicate
    body: "Action"


@record
class Interleave:
    """``A1 ||| A2 ||| …`` (two or more), with empty name sets as in the paper."""

    items: tuple["Action", ...]


@record
class Parallel:
    """``A ⟦ ns1 | cs | ns2 ⟧ B``."""

    left: "Action"
    left_names: tuple[str, ...]
    channels: tuple[str, ...]
    right_names: tuple[str, ...]
    right: "Action"


@record
class Hide:
    action: "Action"
    channels: tuple[str, ...]


@record
class Cond:
    """``if c then A else B`` (the paper's Rule 4 form)."""

    cond: Predicate
    then: "Action"
    orelse: "Action"


@record
class Guard:
    cond: Predicate
    action: "Action"


@record
class Mu:
    """``μ X • A``, where ``A`` mentions ``X`` as ``Call(X)``."""

    var: str
    body: "Action"


@record
class Call:
    """A use of a named action (or of the recursion variable), with arguments."""

    name: str
    args: tuple[ex.Expr, ...] = ()


@record
class Interrupt:
    """``A △ B``."""

    left: "Action"
    right: "Action"


@record
class InterruptCond:
    """``A △ (c)``: ``A`` runs until the condition ``c`` holds."""

    action: "Action"
    cond: Predicate


@record
class Wait:
    """``Wait(n)``: ``n`` tock events, then termination."""

    count: ex.Expr


@record
class Assign:
    """``x1, …, xn := e1, …, en``."""

    targets: tuple[str, ...]
    values: tuple[ex.Expr, ...]


@record
class Spec:
    """``w : [pre, post]``: ``post`` relates the before-state to the after-state of the
    frame ``w``; a frame name in ``post`` means its after-state value (printed primed)."""

    frame: tuple[str, ...]
    pre: Predicate
    post: Predicate


@record
class Evolution:
    """``[Λ S | ∃ L • P]``: the state schema ``S`` evolves over time as the equations ``P``
    say, with the fields of the local schema ``L`` existentially quantified (None: no
    locals); ``Derivative(x)`` is ``x'``."""

    state: str
    locals: str | None
    equations: tuple[ex.Expr, ...]


@record
class VarBlock:
    """``var x : T • A``."""

    var: Binding
    body: "Action"


Action = Union[Skip, Stop, Prefix, Seq, ExtChoice, IndexedExtChoice, Interleave, Parallel,
               Hide, Cond, Guard, Mu, Call, Interrupt, InterruptCond, Wait, Assign, Spec,
               Evolution, VarBlock]

# --------------------------------------------------------------------------- declarations


@record
class Constant:
    """A constant with its value (an expression) or open (None): a parameter of the model.
    ``origin`` is the qualified RoboSim name it comes from."""

    name: str
    type: Type
    value: ex.Expr | None
    origin: str = field(default="", compare=False)  # not printed: the names table has it


@record
class AxDef:
    """Global constants constrained by predicates (Rule 1: ``cycle``, ``tscale``)."""

    constants: tuple[Binding, ...]
    where: tuple[ex.Expr, ...]


@record
class ChannelVariant:
    """One variant of a channel: its tag (the mapped name, or None) and payload types."""

    tag: str | None
    types: tuple[Type, ...]


@record
class ChannelDecl:
    name: str
    variants: tuple[ChannelVariant, ...]


@record
class SchemaField:
    name: str
    type: Type
    visible: bool = False


@record
class Schema:
    name: str
    fields: tuple[SchemaField, ...]


@record
class ActionDef:
    """A named action, possibly parametrised (``MoveCall(lv, av)``)."""

    name: str
    params: tuple[Binding, ...]
    body: Action


@record
class BasicProcess:
    """``process P ≙ begin … end``: constants, the state and local schemas, the named
    actions in define-before-use order and the main action."""

    name: str
    constants: tuple[Constant, ...]
    state: Schema
    local: Schema
    actions: tuple[ActionDef, ...]
    main: Action
    # the declared initial values of locals (name, value): a local that becomes state (an
    # ODE's, in the Isabelle dialects) starts there, else at 0; not printed as such
    initial: tuple[tuple[str, ex.Expr], ...] = field(default=(), compare=False)
    # a scenario's intervals for such locals (name, low, high): Init's specification
    ranges: tuple[tuple[str, ex.Expr, ex.Expr], ...] = field(default=(), compare=False)


@record
class OpaqueProcess:
    """A process declared by name only (the d-model, whose semantics is out of scope)."""

    name: str


@record
class PRef:
    name: str


@record
class PParallel:
    left: "ProcessExpr"
    channels: tuple[str, ...]
    right: "ProcessExpr"


@record
class PHide:
    process: "ProcessExpr"
    channels: tuple[str, ...]


ProcessExpr = Union[PRef, PParallel, PHide]


@record
class ProcessDef:
    name: str
    body: ProcessExpr


@record
class FunctionDecl:
    """An uninterpreted function the equations apply (``ScrewAxis``), with its arity."""

    name: str
    arity: int


@record
class Program:
    """Rule 1: the global constants, the channels and the three processes; ``functions``
    lists the uninterpreted functions so that printers can declare them."""

    globals: AxDef
    channels: tuple[ChannelDecl, ...]
    dmodel: "OpaqueProcess | BasicProcess"  # D: written from its state machine, else opaque
    pmodel: BasicProcess
    system: ProcessDef
    functions: tuple[FunctionDecl, ...] = ()


def program_constants(program: Program) -> tuple[Constant, ...]:
    """Every constant of the program, P's then D's: the theories and the LaTeX document
    declare them all before the processes."""
    return program.pmodel.constants + dmodel_constants(program)


def dmodel_constants(program: Program) -> tuple[Constant, ...]:
    """D's constants: its machine's open constants, when D is written out."""
    dm = program.dmodel
    return dm.constants if isinstance(dm, BasicProcess) else ()


Node = Union[Type, Binding, Exists, Field, Comm, Action, Constant, AxDef, ChannelVariant,
             ChannelDecl, SchemaField, Schema, ActionDef, BasicProcess, OpaqueProcess,
             ProcessExpr, ProcessDef, FunctionDecl, Program]


def children(node: object) -> Iterator[object]:
    """The direct sub-nodes of a node (CyPhyCircus nodes and expressions), in field order."""
    for f in fields(node):  # type: ignore[arg-type]
        value = getattr(node, f.name)
        if isinstance(value, tuple):  # of nodes, or of (name, value…) pairs (``initial``)
            for v in value:
                if isinstance(v, tuple):
                    yield from (w for w in v if not isinstance(w, str))
                elif not isinstance(v, str):
                    yield v
        elif value is not None and not isinstance(value, (str, bool, int, float)):
            yield value


def walk(node: object) -> Iterator[object]:
    """Every node below ``node`` (itself included), expressions too, depth first."""
    stack = [node]
    while stack:
        current = stack.pop()
        yield current
        if isinstance(current, ex.Expr):  # its own walk yields each descendant once
            yield from (c for c in current.walk() if c is not current)
            continue
        stack.extend(reversed(list(children(current))))


def names_in(node: object) -> set[str]:
    """Every variable name mentioned by expressions below ``node`` (not applied functions)."""
    nodes = list(walk(node))
    functions = {id(n.func) for n in nodes if isinstance(n, ex.Call)}
    return {n.text for n in nodes if isinstance(n, ex.Name) and id(n) not in functions}
