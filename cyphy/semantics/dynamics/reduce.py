"""From assembled equations to explicit first-order ODEs ``x' = f(x, u, p)`` with SymPy.

1. Every equation becomes scalar residuals: vectors and matrices component by component by
   the one scalarisation pass that the Isabelle printers use
   (:mod:`cyphy.semantics.scalarise`, components ``X_1`` … ``X_n``), constants with values
   substituted exactly, component by component.
2. Differentiated variables are the candidate states; a residual that mentions no unknown is a
   constraint among states (``e == das - av`` where ``derivative(e)`` appears): the
   constrained variable is solved from it and stops being a state, its derivative obtained by
   differentiating the solution (index reduction), derivatives of inputs becoming inputs.
3. The unknowns (state derivatives and algebraic variables) are matched to residuals
   (NetworkX bipartite matching) and solved block by block in dependency order (strongly
   connected components of the dependency graph: algebraic loops are solved jointly), but only
   the blocks the state derivatives need.
4. What cannot be solved is an obstacle, reported with its equations and variables: an
   unmatched variable (underdetermined), a block SymPy cannot invert, an unknown inside an
   uninterpreted function.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import networkx as nx
import numpy as np
import sympy
from sympy.core.function import AppliedUndef

from cyphy import expr as ex
from cyphy.translate.to_sympy import T, SympyPrinter, UnsupportedNode
from cyphy.lang import ast
from cyphy.diagnostics import Span
from cyphy.model.array import Array
from cyphy.semantics.dynamics.equations import Equation, System
from cyphy.semantics.dynamics.obstacles import Obstacle, competition, in_library, note
from cyphy.semantics.dynamics.solving import (blocks_in_order, cancel_sums, match_unknowns,
                                              solve_linear)
from cyphy.semantics.dynamics.structure import Row, overdetermined, underdetermined
from cyphy.semantics.scalarise.scalariser import Scalariser
from cyphy.semantics.scalarise.shapes import ScalariseError, components, type_shape


@dataclass
class Reduced:
    states: list[str] = field(default_factory=list)
    rhs: dict[str, Any] = field(default_factory=dict)  # state → f(x, u, p) (SymPy)
    inputs: list[str] = field(default_factory=list)
    parameters: list[str] = field(default_factory=list)
    outputs: dict[str, Any] = field(default_factory=dict)  # solved algebraic variables
    obstacles: list[Obstacle] = field(default_factory=list)
    symbols: dict[str, Any] = field(default_factory=dict)  # name → SymPy symbol (plain)
    closed_form: dict[str, Any] | None = None  # state → expression of t and x0
    # named intermediate quantities the rhs and outputs use, in order: (name, value), the
    # value a SymPy expression (an output the equations of motion use) or a
    # ``cyphy.semantics.dynamics.articulated.Polynomial``; empty once inlined (see ``reduce_system``)
    definitions: list[tuple[str, Any]] = field(default_factory=list)


def _exact(v: Any) -> Any:
    if isinstance(v, bool):
        return sympy.true if v else sympy.false
    if isinstance(v, int):
        return sympy.Integer(v)
    if isinstance(v, float):
        return sympy.Rational(repr(v))
    if isinstance(v, (np.ndarray, Array)):
        if v.ndim == 1:
            return sympy.Matrix([_exact(float(x)) for x in v])
        return sympy.Matrix([[_exact(float(x)) for x in row] for row in v])
    return None


class Reducer:
    """``wanted``: algebraic variables to solve as outputs even where no state derivative
    needs them (what cannot be solved among them is left out, not an obstacle)."""

    def __init__(self, system: System, wanted: frozenset[str] = frozenset()) -> None:
        self.system = system
        self.wanted = wanted
        self.funcs: dict[str, Any] = {}  # scalar variable → f(t)
        shapes: dict[str, tuple[int, ...]] = {}
        for name, t in system.variables.items():
            shape = type_shape(t)
            if shape is not None:
                shapes[name] = shape
        symbols: dict[str, Any] = {}
        for name, value in system.parameters.items():
            exact = _exact(value) if value is not None else None
            if isinstance(exact, sympy.MatrixBase):
                shapes[name] = tuple(np.shape(value))
                for k, item in zip(components(name, shapes[name]), list(exact)):
                    symbols[k] = item
            else:
                symbols[name] = exact if exact is not None else sympy.Symbol(name, real=True)
        # variables and valued constants become their components; a constant without a
        # value stays one symbol
        self.scalariser = Scalariser(shapes, frozenset(shapes))
        self.wanted = wanted | {c for n in system.measured  # what the sensors read
                                for c in components(n, shapes.get(n, ()))}
        for name in system.variables:
            for k in components(name, shapes.get(name, ())):
                symbols[k] = self._func(k)
        # definitions (equations of motion) are plain symbols that stand for their values:
        # each hides the variables it depends on, which order the solving but are never
        # solved from an equation that mentions only the definition
        self.hidden: dict[str, frozenset[str]] = {}
        for d in system.definitions:
            names: set[str] = set()
            for atom in d.value.atoms():
                names |= self.hidden.get(atom, {atom})
            self.hidden[d.name] = frozenset(names)
            symbols[d.name] = sympy.Symbol(d.name, real=True)
        self.printer = SympyPrinter(symbols=symbols)
        self.inputs = {c for n in system.inputs for c in self._components(n)}
        self.input_derivatives: dict[Any, Any] = {}
        self.static: dict[Any, Any] = {}  # algebraic variables solved without states
        self._atom_cache: dict[tuple[Any, Any], frozenset[Any]] = {}

    def _atoms(self, r: Any, kind: Any = None) -> frozenset[Any]:
        """``r.atoms(kind)`` (``r.free_symbols`` for None), remembered: the matching and the
        index reduction ask the same residuals again and again (a traversal each time was
        a fifth of a 50-link motor chain's reduction, measured)."""
        key = (r, kind)
        found = self._atom_cache.get(key)
        if found is None:
            found = frozenset(r.free_symbols if kind is None else r.atoms(kind))
            self._atom_cache[key] = found
        return found

    def _func(self, name: str) -> Any:
        f = sympy.Function(name, real=True)(T)
        self.funcs[name] = f
        return f

    def _components(self, name: str) -> list[str]:
        return components(name, self.scalariser.shapes.get(name, ()))

    # ----- step 1: residuals
    def residuals(self, obstacles: list[Obstacle]) -> list[tuple[Any, Equation]]:
        out: list[tuple[Any, Equation]] = []
        for eq in self.system.equations:
            e = eq.expr
            if not (isinstance(e, ex.BinOp) and e.op == "=="):
                obstacles.append(Obstacle("unsupported", f"'{eq.origin}' has an equation that "
                                          "is not lhs == rhs", (), (eq,)))
                continue
            try:
                scalar = self.scalariser.predicate(e)
                sides = [(self.printer.doprint(q.left), self.printer.doprint(q.right))
                         for q in scalar if isinstance(q, ex.BinOp)]
            except (ScalariseError, UnsupportedNode, TypeError, ValueError,
                    sympy.ShapeError) as err:
                obstacles.append(Obstacle("unsupported", f"cannot convert an equation of "
                                          f"{eq.origin}: {err}", (), (eq,)))
                continue
            out.extend(((left - right).doit(), eq) for left, right in sides)
        return out

    def _derivative_symbol(self, f: Any) -> Any:
        return sympy.Symbol(f"d_{f.func.__name__}", real=True)

    def reduce(self) -> Reduced:
        result = Reduced()
        residuals = self.residuals(result.obstacles)
        residuals = self._higher_derivatives(residuals)
        if not result.obstacles:
            result.obstacles.extend(self._structure(residuals))
        if result.obstacles:
            result.obstacles = [self.placed(o) for o in result.obstacles]
            return result  # never a reduction that leaves an equation out
        states: set[str] = set()
        for r, _ in residuals:
            for d in sorted(r.atoms(sympy.Derivative), key=str):
                name = d.expr.func.__name__
                if name in self.inputs:
                    continue
                states.add(name)
        while True:
            residuals, presolved = self._presolve_static(residuals, states)
            residuals, states, reduced = self._index_reduction(residuals, states, result)
            if not presolved and not reduced and not self._uncover(residuals, states):
                break
        residuals = [(self._input_derivatives(r), eq) for r, eq in residuals]
        dsyms = {self._derivative_symbol(self.funcs[s]): s for s in sorted(states)}
        to_symbol = {sympy.Derivative(self.funcs[s], T): self._derivative_symbol(self.funcs[s])
                     for s in states}
        rs = [(r.xreplace(to_symbol), eq) for r, eq in residuals]
        static = {f.func.__name__ for f in self.static}  # solved already: known
        algebraic = sorted(n for n in self.funcs
                           if n not in states and n not in self.inputs and n not in static)
        unknown_of = {self.funcs[n]: n for n in algebraic}
        unknown_of.update({d: f"d_{s}" for d, s in dsyms.items()})
        self._solve(rs, unknown_of, dsyms, result)
        result.states = sorted(s for s in states if s in result.rhs)
        used = set().union(*(sympy.sympify(v).free_symbols | {f.func.__name__ for f in
                                                               sympy.sympify(v).atoms(
                                                                   sympy.Function)}
                             for v in result.rhs.values())) if result.rhs else set()
        if self.system.definitions and result.rhs:
            used |= self._definitions(result)
        # and what the outputs use, so that every name they mention is defined (an input
        # such as a root joint's parent twist, which only an output reads)
        used |= set().union(*(sympy.sympify(v).free_symbols for v in result.outputs.values()))
        used_names = {str(u) for u in used}
        result.inputs = sorted(n for n in self.inputs | {str(s) for s in
                                                          self.input_derivatives.values()}
                               if n in used_names)
        result.parameters = sorted(str(s) for s in used if isinstance(s, sympy.Symbol)
                                   and str(s) in self.system.parameters)
        result.obstacles = [self.placed(o) for o in result.obstacles]
        return result

    # ----- structural analysis (before any reduction)
    def _structure(self, residuals: list[tuple[Any, Equation]]) -> list[Obstacle]:
        """The structural analysis (:mod:`cyphy.semantics.dynamics.structure`) as obstacles:
        equations left over (the device equations and equations of motion are matched first,
        then mappings' equations, then relations, so what is left over is the user's), else
        the free variables the evolution needs."""
        efforts = {c for n in self.system.efforts for c in self._components(n)}
        rows: list[Row[Equation]] = []
        for r, eq in residuals:
            direct = {f.func.__name__ for f in self._atoms(r, AppliedUndef)
                      if f.func.__name__ in self.funcs} - self.inputs
            hidden = self._hidden_in(r) - self.inputs
            derived = {d.expr.func.__name__ for d in self._atoms(r, sympy.Derivative)} & direct
            motion = eq.origin.endswith(" motion")
            rows.append(Row(eq, frozenset(direct | hidden),
                            frozenset(direct - efforts if motion else direct),
                            frozenset(derived)))
        rank = {"relation": 2, "mapping": 1}
        rows.sort(key=lambda row: rank.get(row.equation.origin.split()[0], 0))
        competitions = overdetermined(rows)
        if competitions:
            return [competition(c) for c in competitions]
        states = set().union(*(r.differentiated for r in rows))
        freedom = underdetermined(rows, states)
        if freedom is None:
            return []
        names = ", ".join(freedom.variables)
        evolving = [v for v in freedom.variables if v in states]
        what = (f"how {', '.join(evolving)} evolve" if evolving else
                f"{names}, which the evolution needs")
        more = "one unknown" if freedom.free == 1 else f"{freedom.free} unknowns"
        return [Obstacle("underdetermined", f"the equations do not determine {what}: among "
                         f"{names} there is {more} more than equations", freedom.variables,
                         freedom.equations)]

    def placed(self, o: Obstacle) -> Obstacle:
        """``o`` reported in the user's files: at its first equation written there, or else at
        the element whose library device the equation comes from; one note per equation."""
        def place(eq: Equation) -> Span | None:
            if not in_library(eq.span):
                return eq.span
            return self.system.places.get(eq.origin)

        spans = [s for s in (place(eq) for eq in o.equations) if s is not None]
        notes = list(o.notes) or [note(eq, self.system.places) for eq in o.equations]
        return replace(o, span=o.span or (spans[0] if spans else None), notes=tuple(notes))

    def _definitions(self, result: Reduced) -> set[Any]:
        """Fill ``result.definitions``: the outputs the definitions use (a joint's effort
        from the motor that drives it), then the definitions; returns the symbols they use."""
        hidden = set().union(*self.hidden.values())
        first = [(n, result.outputs[n]) for n in sorted(hidden) if n in result.outputs]
        result.definitions = first + [(d.name, d.value) for d in self.system.definitions]
        used: set[Any] = set()
        for _, value in first:
            used |= value.free_symbols
        for d in self.system.definitions:
            used |= {sympy.Symbol(a, real=True) for a in d.value.atoms()}
        return used - {sympy.Symbol(d.name, real=True) for d in self.system.definitions}

    def _higher_derivatives(self, residuals: list[tuple[Any, Equation]]
                            ) -> list[tuple[Any, Equation]]:
        """A second derivative of x introduces the state ``x_dot`` with x' = x_dot."""
        extra: list[tuple[Any, Equation]] = []
        out = []
        for r, eq in residuals:
            for d in sorted(r.atoms(sympy.Derivative), key=str):
                if d.derivative_count >= 2 and d.expr.func.__name__ in self.funcs:
                    name = d.expr.func.__name__
                    dot = self.funcs.get(f"{name}_dot") or self._func(f"{name}_dot")
                    self.system.variables.setdefault(f"{name}_dot",
                                                     ast.PrimitiveType("real"))
                    r = r.subs(d, sympy.Derivative(dot, (T, d.derivative_count - 1)))
                    pair = (sympy.Derivative(d.expr, T) - dot, eq)
                    if not any(p[0] == pair[0] for p in extra):
                        extra.append(pair)
            out.append((r, eq))
        return out + extra if not extra else self._higher_derivatives(out + extra)

    def _hidden_in(self, r: Any) -> set[str]:
        """The variables that the definitions ``r`` mentions depend on."""
        if not self.hidden:
            return set()
        out: set[str] = set()
        for s in self._atoms(r):
            out |= self.hidden.get(s.name, frozenset())
        return {n for n in out if n in self.funcs}

    def _unknowns_in(self, r: Any, states: set[str]) -> set[str]:
        names = {f.func.__name__ for f in self._atoms(r, sympy.Function) if f.func.__name__ in
                 self.funcs} | self._hidden_in(r)
        derivs = {d.expr.func.__name__ for d in self._atoms(r, sympy.Derivative)}
        algebraic = {n for n in names if n not in states and n not in self.inputs}
        return algebraic | {f"d_{n}" for n in derivs if n in states}

    def _index_reduction(self, residuals: list[tuple[Any, Equation]], states: set[str],
                         result: Reduced) -> tuple[list[tuple[Any, Equation]], set[str]]:
        """A residual with no unknown constrains the states: solve it for one of them,
        which then becomes algebraic (its derivative from differentiating the solution)."""
        changed, any_change = True, False
        # whether each residual mentions an unknown (or a definition), kept up to date for
        # the residuals a substitution changes: rescanning them all after every change made
        # this quadratic in the size of the model (15 s of a 30-link chain's 60, measured)
        blocked = [bool(self._unknowns_in(r, states) or self._hidden_in(r))
                   for r, _ in residuals]
        mentions = [{g.func.__name__ for g in self._atoms(r, AppliedUndef)}
                    for r, _ in residuals]
        while changed:
            changed = False
            for i, (r, eq) in enumerate(residuals):
                if blocked[i]:
                    continue
                candidates = sorted(n for n in self._names(r) if n in states)
                if not candidates:
                    continue  # a relation among inputs and parameters: nothing to solve
                lhs = eq.expr.left if isinstance(eq.expr, ex.BinOp) else None
                preferred = [n for n in candidates if isinstance(lhs, ex.Name)
                             and lhs.text == n] or candidates
                name = preferred[0]
                f = self.funcs[name]
                linear = solve_linear([r], [f])
                solutions = [linear[0][f]] if linear else sympy.solve(r, f)
                if len(solutions) != 1:
                    result.obstacles.append(Obstacle(
                        "algebraic-loop", f"the constraint from {eq.origin} cannot be solved "
                        f"for {name}", (name,), (eq,)))
                    residuals.pop(i)
                    blocked.pop(i)
                    mentions.pop(i)
                    changed = True
                    break
                value = solutions[0]
                residuals.pop(i)
                blocked.pop(i)
                mentions.pop(i)
                states.discard(name)
                derivative = sympy.diff(value, T)
                for k, (x, e) in enumerate(residuals):
                    if name not in mentions[k]:
                        continue
                    x = sympy.expand(x.xreplace({sympy.Derivative(f, T): derivative})
                                     .xreplace({f: value}))
                    residuals[k] = (x, e)
                    mentions[k] = {g.func.__name__ for g in self._atoms(x, AppliedUndef)}
                    blocked[k] = bool(self._unknowns_in(x, states) or self._hidden_in(x))
                residuals.append((f - value, eq))  # keeps `name` as an output
                blocked.append(True)  # `name` is now algebraic: an unknown
                mentions.append({name} | {g.func.__name__ for g in value.atoms(AppliedUndef)})
                changed = any_change = True
                break
        return residuals, states, any_change

    def _uncover(self, residuals: list[tuple[Any, Equation]], states: set[str]) -> bool:
        """Bring a hidden constraint among states to light: a residual that no matching of
        unknowns can use (``lv == v`` when ``e == dls - lv`` already determines lv and e is a
        state) has its algebraic unknowns replaced by what their own equations give, when
        those are explicit (no derivative, linear in the unknown), so that it becomes a
        constraint the index reduction differentiates. Returns whether anything changed."""
        unknowns = [self._unknowns_in(r, states) for r, _ in residuals]
        defined_by = match_unknowns(list(enumerate(unknowns)))
        used = set(defined_by.values())
        for i, (r, _) in enumerate(residuals):
            if i in used or not unknowns[i]:
                continue
            for y in sorted(v for v in unknowns[i] if not v.startswith("d_")):
                j = defined_by.get(y)
                if j is None or self._atoms(residuals[j][0], sympy.Derivative) or \
                        self._hidden_in(residuals[j][0]):
                    continue
                f = self.funcs[y]
                solution = solve_linear([residuals[j][0]], [f])
                if solution is None:
                    continue
                value = solution[0][f]
                for k, (x, eq) in enumerate(residuals):
                    if k != j and x.has(f):
                        residuals[k] = (sympy.expand(x.xreplace({sympy.Derivative(f, T):
                                                                 sympy.diff(value, T)})
                                                     .xreplace({f: value})), eq)
                return True
        return False

    def _presolve_static(self, residuals: list[tuple[Any, Equation]], states: set[str]
                         ) -> tuple[list[tuple[Any, Equation]], bool]:
        """Solve the algebraic variables that do not depend on states (a mapping's wheel
        speeds from the operation's arguments, a sensor's output from its input) and
        substitute them, so that constraints they hide among states come to light."""
        static = [(i, r) for i, (r, _) in enumerate(residuals)
                  if not self._atoms(r, sympy.Derivative) and not (self._names(r) & states)]
        unknown_of = {self.funcs[n]: n for n in sorted(set().union(*(self._names(r)
                      for _, r in static))) if n not in self.inputs} if static else {}
        if not unknown_of:
            return residuals, False
        defined_by = match_unknowns([(i, self._unknown_names(r, unknown_of, hidden=False))
                             for i, r in static])
        deps = nx.DiGraph()
        for name, i in sorted(defined_by.items()):
            deps.add_node(name)
            for other in sorted(self._unknown_names(residuals[i][0], unknown_of)):
                deps.add_edge(other, name)
        undefined = set(unknown_of.values()) - set(defined_by)
        solved: dict[Any, Any] = {}
        used: set[int] = set()
        for block in blocks_in_order(deps):
            if any(p in undefined for b in block for p in deps.predecessors(b)) or \
                    any(b in undefined for b in block):
                undefined.update(block)
                continue
            eqs = [residuals[defined_by[v]][0].xreplace(solved) for v in block]
            objs = [self.funcs[v] for v in block]
            solution = solve_linear(eqs, objs)
            if solution is None:
                try:
                    solution = sympy.solve(eqs, objs, dict=True)
                except (NotImplementedError, ValueError):
                    solution = []
            if len(solution) != 1 or set(solution[0]) != set(objs):
                undefined.update(block)
                continue
            solved.update({k: cancel_sums(v) for k, v in solution[0].items()})
            used.update(defined_by[v] for v in block)
        if not solved:
            return residuals, False
        out = [(sympy.expand(r.xreplace(solved)), eq) for i, (r, eq) in enumerate(residuals)
               if i not in used]
        self.static.update(solved)
        return out, True

    def _input_derivatives(self, r: Any) -> Any:
        for d in r.atoms(sympy.Derivative):
            name = d.expr.func.__name__
            if name in self.inputs:
                sym = self.input_derivatives.setdefault(
                    d, sympy.Symbol(f"der_{name}", real=True))
                r = r.subs(d, sym)
        return r

    def _names(self, r: Any) -> set[str]:
        return {f.func.__name__ for f in self._atoms(r, sympy.Function) if f.func.__name__ in
                self.funcs} | self._hidden_in(r)

    # ----- step 3: matching and block solving
    def _solve(self, residuals: list[tuple[Any, Equation]], unknown_of: dict[Any, str],
               dsyms: dict[Any, str], result: Reduced) -> None:
        by_name = {v: k for k, v in unknown_of.items()}
        defined_by = match_unknowns([(i, self._unknown_names(r, unknown_of, hidden=False))
                             for i, (r, _) in enumerate(residuals)])
        deps = nx.DiGraph()
        for name, i in sorted(defined_by.items()):
            deps.add_node(name)
            for other in sorted(self._unknown_names(residuals[i][0], unknown_of)):
                if other != name:
                    deps.add_edge(other, name)

        def closure(frontier: list[str]) -> set[str]:
            seen: set[str] = set()
            while frontier:
                v = frontier.pop()
                if v in seen:
                    continue
                seen.add(v)
                if v in defined_by:
                    frontier.extend(self._unknown_names(residuals[defined_by[v]][0],
                                                        unknown_of))
            return seen

        needed = closure([f"d_{s}" for s in dsyms.values()])
        extra = closure([v for v in sorted(self.wanted) if v in by_name]) - needed
        missing = sorted(v for v in needed if v not in defined_by)
        blocked: set[str] = {v for v in extra if v not in defined_by}
        for v in missing:
            users = [residuals[i][1] for n, i in defined_by.items()
                     if v in self._unknown_names(residuals[i][0], unknown_of)]
            shown = v[2:] + "'" if v.startswith("d_") else v
            result.obstacles.append(Obstacle(
                "underdetermined", f"no equation determines {shown}", (shown,),
                tuple(dict.fromkeys(users))))
            blocked.add(v)
        solved: dict[Any, Any] = {}
        sub = deps.subgraph((needed | extra) & set(defined_by))
        for block in blocks_in_order(sub):
            if any(p in blocked for b in block for p in deps.predecessors(b)):
                blocked.update(block)
                continue
            quiet = not needed.intersection(block)  # only wanted: no obstacle
            eqs = [residuals[defined_by[v]][0].xreplace(solved) for v in block]
            objs = [by_name[v] for v in block]
            functions = [f for e in eqs for f in e.atoms(AppliedUndef)
                         if f.func.__name__ not in self.funcs and any(f.has(o) for o in objs)]
            if functions:
                if not quiet:
                    undefined = ", ".join(sorted({str(f.func) for f in functions}))
                    result.obstacles.append(Obstacle(
                        "unknown-function", f"{undefined} has no definition: "
                        f"{', '.join(_shown(v) for v in block)} cannot be solved through it",
                        tuple(_shown(v) for v in block),
                        tuple(residuals[defined_by[v]][1] for v in block)))
                blocked.update(block)
                continue
            solution = solve_linear(eqs, objs)
            if solution is None:
                try:
                    solution = sympy.solve(eqs, objs, dict=True)
                except (NotImplementedError, ValueError) as err:
                    solution, _ = [], err
            if len(solution) != 1 or set(solution[0]) != set(objs):
                if not quiet:
                    result.obstacles.append(Obstacle(
                        "algebraic-loop", "SymPy cannot solve " + ", ".join(
                            _shown(v) for v in block) + " from their equations (a "
                        "non-invertible algebraic loop)", tuple(_shown(v) for v in block),
                        tuple(residuals[defined_by[v]][1] for v in block)))
                blocked.update(block)
                continue
            for obj, value in solution[0].items():
                solved[obj] = cancel_sums(value)
        plain = {f: sympy.Symbol(f.func.__name__, real=True) for f in self.funcs.values()}
        plain.update({d: sym for d, sym in self.input_derivatives.items()})
        for d, s in dsyms.items():
            if d in solved:
                result.rhs[s] = sympy.expand(solved[d].xreplace(plain))
        for obj, value in solved.items():
            name = unknown_of[obj]
            if not name.startswith("d_"):
                result.outputs[name] = sympy.expand(value.xreplace(plain))
        for obj, value in self.static.items():
            result.outputs[obj.func.__name__] = sympy.expand(value.xreplace(plain))
        result.symbols = {str(s): s for s in plain.values()}

    def _unknown_names(self, r: Any, unknown_of: dict[Any, str], hidden: bool = True
                       ) -> set[str]:
        """The unknowns ``r`` mentions; with ``hidden``, also those its definitions depend on
        (for the order of solving, not for matching: ``r`` cannot be solved for them)."""
        present = self._atoms(r, AppliedUndef) | self._atoms(r)
        out = {unknown_of[a] for a in present if a in unknown_of}
        if hidden and self.hidden:
            out |= {n for n in self._hidden_in(r) if self.funcs[n] in unknown_of}
        return out


def _shown(v: str) -> str:
    return v[2:] + "'" if v.startswith("d_") else v


def reduce_system(system: System, wanted: frozenset[str] = frozenset()) -> Reduced:
    """The explicit ODEs of ``system``; ``wanted`` algebraic variables are solved as outputs
    too where they can be (the axiomatic Isabelle dialect wants every state field). The
    system's definitions (the equations of motion's named quantities: ``assemble``'s
    ``definitions``) stay names, listed in order in ``Reduced.definitions``."""
    return Reducer(system, wanted).reduce()
