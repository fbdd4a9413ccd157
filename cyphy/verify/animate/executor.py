"""Runs the composition ``(D [| cs |] P) \\ cs`` of a read theory: each process is a stack of
actions over its own state; an event in ``cs`` happens when both offer it (an output's value
binds the other's input), ``Evolve △ cond`` integrates the p-model's ODE until the condition
holds. Time passes only in Evolve; the ``tock``s mark the cycles between."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from cyphy.verify.animate.errors import AnimateError
from cyphy.verify.animate.model import Definition, TheoryModel
from cyphy.verify.animate.terms import Unsupported, evaluate, op_name, place

#: Events at one instant before the run is called a livelock (no time passes).
MAX_EVENTS_PER_INSTANT = 100_000
#: Interleavings entered inside one another while looking for the next event: past this a
#: recursion runs through ``|||`` (``μ Y • (A ||| Y) □ …``), whose offers have no end.
MAX_INTERLEAVING_DEPTH = 32

Frame = tuple[Any, dict[str, Any]]


@dataclass(frozen=True)
class MuBinding:
    """What a recursion variable ``X`` of ``MuC (λ X. body)`` stands for."""

    body: Any
    env: dict[str, Any] = field(hash=False, compare=False)


@dataclass
class Proc:
    """One process: its state (None: not yet given a value) and what it does next."""

    name: str
    state: dict[str, Any]
    stack: list[Frame]
    assigned: set[str] = field(default_factory=set)


@dataclass
class Offer:
    channel: str
    kind: str            # "out", "in" or "plain"
    value: Any           # out: the value; in: the binders' names
    proc: Proc           # the process as it is after the event (binders still to bind)
    binder: Proc | None = None  # whose next action the input binds (a branch of |||)


@dataclass
class Evolving:
    tree: Any            # the ``exists`` node of EvolveC
    until: Any           # the interrupt's condition (uexpr)
    env: dict[str, Any]
    proc: Proc


class Runner:
    """Executes actions of one theory; ``settle(name, proc)`` gives an algebraic state's
    value when a discrete action reads one that no action has set (Evolve's equations)."""

    def __init__(self, model: TheoryModel, constant: Callable[[str], Any],
                 settle: Callable[[str, Proc], Any],
                 choose: Callable[[list[str], Proc], list[float]] | None = None) -> None:
        self.model = model
        self.constant = constant
        self.settle = settle
        self.choose = choose  # a frame with any values (the axiomatic dialect's rates)
        self.where: Definition | None = None
        self._specs: dict[int, tuple[Callable[..., Any], list[str]]] = {}
        self._interleaving_depth = 0

    # values -------------------------------------------------------------------------
    def value(self, node: Any, proc: Proc, env: dict[str, Any]) -> Any:
        def state(x: str) -> Any:
            if x not in proc.state:
                raise Unsupported(f"the name {x}, which is not in {proc.name}'s state")
            v = proc.state[x]
            return self.settle(x, proc) if v is None else v

        def name(x: str) -> Any:
            if x in env and not isinstance(env[x], MuBinding):
                return env[x]
            return self.constant(x)

        try:
            return evaluate(node, state, lambda x: _no_rate(x), name)
        except Unsupported as err:
            raise self._here(err) from None

    def _open_value(self, node: Any, proc: Proc, env: dict[str, Any]) -> Any:
        """An assigned value; in the axiomatic dialect, whose main action re-establishes
        every output before Evolve, None (left open) for one over a constant without a
        value (a sensor no --const describes): only what reads it needs it."""
        try:
            return self.value(node, proc, env)
        except AnimateError as err:
            if err.code == "E-ANIMATE-CONST" and self.model.dialect == "axiomatic":
                return None
            raise

    def _here(self, err: Unsupported) -> AnimateError:
        if self.where is None:
            return AnimateError("E-ANIMATE-UNSUPPORTED", str(err), path=self.model.path,
                                status=2)
        return place(err, self.where)

    # stepping -----------------------------------------------------------------------
    def run(self, proc: Proc) -> list[Offer] | Evolving | None:
        """Internal steps until the process offers events (a list, empty when it deadlocks),
        evolves, or ends (None)."""
        while proc.stack:
            node, env = proc.stack.pop()
            if isinstance(node, tuple) and node[0] == "tocks":
                if node[1] <= 0:
                    continue
                if node[1] > 1:
                    proc.stack.append((("tocks", node[1] - 1), env))
                return [Offer("tock", "plain", None, proc)]
            if isinstance(node, tuple) and node[0] == "interleave":
                got = self._interleave(proc, node, env)
                if got is None:
                    continue  # every branch has ended
                return got
            kind = node.data
            ch = node.children
            if kind == "skip":
                continue
            if kind == "stop":
                return []
            if kind in ("call", "call_args"):
                self._call(proc, node, env)
                continue
            if kind == "seq":
                proc.stack.append((ch[1], env))
                proc.stack.append((ch[0], env))
                continue
            if kind == "prefix":
                proc.stack.append((ch[1], env))
                return [self._offer(ch[0], proc, env)]
            if kind == "ext_choice":
                offers: list[Offer] = []
                for branch in (ch[0], ch[1]):
                    copy = Proc(proc.name, dict(proc.state), list(proc.stack) + [(branch, env)],
                                set(proc.assigned))
                    got = self.run(copy)
                    if not isinstance(got, list):
                        raise self._here(Unsupported("an external choice whose branch does "
                                                     "not start with an event"))
                    offers += got
                return offers
            if kind == "interleave":
                # ``A ||| B`` with empty name sets: each branch runs on its own copy of the
                # state, and the state from before is what follows (utp-main c9122f14,
                # utp_circus_parallel.thy:18-26, 846-847): the outer state is left alone
                branches = tuple(Proc(proc.name, dict(proc.state), [(branch, env)],
                                      set(proc.assigned)) for branch in ch)
                proc.stack.append((("interleave", branches), env))
                continue
            if kind == "cond":
                test = self.value(ch[1], proc, env)
                proc.stack.append((ch[0] if test else ch[2], env))
                continue
            if kind == "guard":
                if not self.value(ch[0], proc, env):
                    return []
                proc.stack.append((ch[1], env))
                continue
            if kind == "indexed_choice":
                # ``□ x ∈ UNIV • (p(x) & A(x))``: A for the value of x that p determines (a
                # typed event's value: Rule 5's equations), or 0 when p is true (Rule 4's
                # else-branch leaves the value of an event that did not occur free)
                var, where, body = str(ch[0]), ch[2], ch[3]
                inner = dict(env)
                inner[var] = self._chosen(var, where, proc, env)
                proc.stack.append((body, inner))
                continue
            if kind == "mu":
                var = str(ch[0])
                inner = dict(env)
                inner[var] = MuBinding(ch[1], inner)
                proc.stack.append((ch[1], inner))
                continue
            if kind == "wait":
                if str(ch[0]) != "tock":
                    raise self._here(Unsupported(f"WaitC over the event {ch[0]}"))
                n = self.value(ch[1], proc, env)
                proc.stack.append((("tocks", int(n)), env))
                continue
            if kind == "assign_one":
                self._assign(proc, [str(ch[0])], [self.value(ch[1], proc, env)])
                continue
            if kind == "assign":
                names = [str(c) for c in ch if not hasattr(c, "data")]
                exprs = [c for c in ch if hasattr(c, "data")]
                self._assign(proc, names, [self._open_value(e, proc, env) for e in exprs])
                continue
            if kind == "spec":
                self._spec(proc, node, env)
                continue
            if kind == "choose" and self.choose is not None:
                frame = [str(c) for c in ch[0].children]
                self._assign(proc, frame, self.choose(frame, proc))
                continue
            if kind == "interrupt_cond":
                target = self._evolution(ch[0], env)
                return Evolving(target, ch[1], env, proc)
            raise self._here(Unsupported(f"the action {kind}"))
        return None

    def _interleave(self, proc: Proc, node: tuple[str, tuple[Proc, ...]],
                    env: dict[str, Any]) -> list[Offer] | None:
        """The events either branch of an interleaving offers, each leading to the whole
        process with that branch advanced; None when every branch has ended."""
        branches = node[1]
        offers: list[Offer] = []
        ended = True
        if self._interleaving_depth >= MAX_INTERLEAVING_DEPTH:
            raise self._here(Unsupported(f"the action interleave nested more than "
                                         f"{MAX_INTERLEAVING_DEPTH} deep before any event (a "
                                         "recursion through |||)"))
        for i, branch in enumerate(branches):
            self._interleaving_depth += 1
            try:
                got = self.run(Proc(branch.name, dict(branch.state), list(branch.stack),
                                    set(branch.assigned)))
            finally:
                self._interleaving_depth -= 1
            if got is None:
                continue
            ended = False
            if not isinstance(got, list):
                raise self._here(Unsupported("an evolution inside an interleaving"))
            for o in got:
                after = branches[:i] + (o.proc,) + branches[i + 1:]
                whole = Proc(proc.name, dict(proc.state),
                             list(proc.stack) + [(("interleave", after), env)],
                             set(proc.assigned))
                offers.append(Offer(o.channel, o.kind, o.value, whole, o.binder or o.proc))
        return None if ended else offers

    def _call(self, proc: Proc, node: Any, env: dict[str, Any]) -> None:
        name = str(node.children[0])
        bound = env.get(name)
        if isinstance(bound, MuBinding):
            proc.stack.append((bound.body, bound.env))
            return
        definition = self.model.definitions.get(name)
        if definition is None:
            raise self._here(Unsupported(f"the action {name}, which is not defined"))
        args = [self.value(a, proc, env) for a in node.children[1:]]
        if len(args) != len(definition.params):
            raise self._here(Unsupported(f"{name} with {len(args)} arguments"))
        self.where = definition
        proc.stack.append((definition.tree, dict(zip(definition.params, args))))

    def _evolution(self, node: Any, env: dict[str, Any]) -> Any:
        if node.data == "call" and str(node.children[0]) in self.model.definitions:
            node = self.model.definitions[str(node.children[0])].tree
        if node.data != "evolution":
            raise self._here(Unsupported("an interrupt of an action other than EvolveC"))
        return node.children[0]

    def _offer(self, event: Any, proc: Proc, env: dict[str, Any]) -> Offer:
        ch = event.children
        channel = str(ch[0])
        if event.data == "event_plain":
            return Offer(channel, "plain", None, proc)
        if event.data in ("event_out", "event_dot"):
            return Offer(channel, "out", self.value(ch[1], proc, env), proc)
        return Offer(channel, "in", [str(c) for c in ch[1:]], proc)

    def _assign(self, proc: Proc, names: list[str], values: list[Any]) -> None:
        for n, v in zip(names, values):
            if n not in proc.state:
                raise self._here(Unsupported(f"an assignment to {n}, not in {proc.name}'s "
                                             "state"))
            if isinstance(v, float) and v != v:
                raise AnimateError("E-ANIMATE-VALUE", f"{n} is assigned NaN", status=1)
            proc.state[n] = v
            proc.assigned.add(n)

    def _spec(self, proc: Proc, node: Any, env: dict[str, Any]) -> None:
        """``frame:[pre, post]``: the frame's new values, solved from the post's equations
        (once per statement, over its parameters and the state it reads)."""
        frame = [str(c) for c in node.children[0].children]
        if not self.value(node.children[1], proc, env):
            raise AnimateError("E-ANIMATE-PRE", f"a call's precondition is false in "
                               f"{self.where.name if self.where else 'the theory'}", status=1)
        self._assign(proc, frame, self._solved(node.children[2], frame, proc, env,
                                               "its postcondition"))

    def _chosen(self, var: str, where: Any, proc: Proc, env: dict[str, Any]) -> Any:
        """The value of an indexed choice's variable: the one its predicate determines, 0
        when the predicate is ``true`` (any value: the theory leaves it free)."""
        conjuncts = [c for c in where.children if getattr(c, "data", "") != "binder"]
        if all(getattr(c, "data", "") in ("utrue", "true") for c in conjuncts):
            return 0.0
        return self._solved(where, [var], proc, env, "the choice's predicate")[0]

    def _solved(self, post: Any, frame: list[str], proc: Proc, env: dict[str, Any],
                what: str) -> list[float]:
        """The frame's values that the equations ``post`` (an ``exists`` node) give, solved
        once per node over the parameters and the state they read."""
        key = id(post)
        if key not in self._specs:
            self._specs[key] = self._solve_spec(post, frame, proc, env, what)
        solution, reads = self._specs[key]
        args = [env[x] if x in env else (proc.state.get(x) if proc.state.get(x) is not None
                                         else self.settle(x, proc)) for x in reads]
        return [float(v) for v in solution(*args)]

    def _solve_spec(self, post: Any, frame: list[str], proc: Proc,
                    env: dict[str, Any], what: str) -> tuple[Callable[..., Any], list[str]]:
        import sympy  # lazy: only calls with a specification statement need it
        binders = [str(b.children[0]) for b in post.children if getattr(b, "data", "") == "binder"]
        syms = {x: sympy.Symbol(x) for x in frame + binders}
        reads: dict[str, Any] = {}

        def state(x: str) -> Any:
            if x in syms:
                return syms[x]
            return reads.setdefault(x, sympy.Symbol("s__" + x))

        def name(x: str) -> Any:
            if x in syms:
                return syms[x]
            if x in env:
                return reads.setdefault(x, sympy.Symbol("p__" + x))
            return self.constant(x)

        eqs = []
        try:
            for c in post.children:
                if getattr(c, "data", "") == "binder":
                    continue
                n = c.children[0] if c.data == "lifted" else c
                if n.data != "binop" or op_name(n.children[1]) != "=":
                    raise Unsupported("a postcondition conjunct that is not an equation")
                eqs.append(sympy.sympify(evaluate(n.children[0], state, _no_rate, name))
                           - evaluate(n.children[2], state, _no_rate, name))
        except Unsupported as err:
            raise self._here(err) from None
        answers = sympy.solve(eqs, list(syms.values()), dict=True, rational=False)
        if len(answers) != 1 or any(syms[x] not in answers[0] for x in frame):
            raise AnimateError("E-ANIMATE-SPEC", f"{self.where.name if self.where else 'a call'}"
                               f": {what} does not determine {', '.join(frame)}",
                               path=self.where.path if self.where else None,
                               line=self.where.line if self.where else 0, status=1)
        names = list(reads)
        solution = sympy.lambdify([reads[x] for x in names], [answers[0][syms[x]] for x in frame],
                                  modules="math")
        return solution, names


def _no_rate(x: str) -> Any:
    raise Unsupported(f"the rate of {x} outside Evolve")


def synchronise(left: list[Offer], right: list[Offer], cs: set[str]) \
        -> tuple[str, Any, Proc | None, Proc | None] | None:
    """The first event both sides agree on (or one side's event outside ``cs``): the
    channel, the value exchanged, and each side's process after it (None: it did not
    take part)."""
    for offers, mine in ((left, 0), (right, 1)):
        for o in offers:
            if o.channel not in cs:
                return o.channel, o.value, (o.proc if mine == 0 else None), \
                    (o.proc if mine == 1 else None)
    for a in left:
        for b in right:
            if a.channel != b.channel:
                continue
            if a.kind == "out" and b.kind == "in":
                _bind(b, a.value)
                return a.channel, a.value, a.proc, b.proc
            if a.kind == "in" and b.kind == "out":
                _bind(a, b.value)
                return a.channel, b.value, a.proc, b.proc
            if a.kind == b.kind == "plain":
                return a.channel, None, a.proc, b.proc
            if a.kind == b.kind == "out" and a.value == b.value:
                return a.channel, a.value, a.proc, b.proc
    return None


def _bind(offer: Offer, value: Any) -> None:
    """An input's names bound to the value (a tuple gives one component to each)."""
    names = offer.value
    parts = value if len(names) > 1 else (value,)
    target = offer.binder or offer.proc
    node, env = target.stack[-1] if target.stack else (None, {})
    bound = dict(env)
    bound.update(zip(names, parts))
    if target.stack:
        target.stack[-1] = (node, bound)
