"""Explicit joint accelerations of a kinematic tree as a linear-size sequence of named
definitions: the articulated-body algorithm (Featherstone, *Rigid Body Dynamics Algorithms*,
2008, ch. 7, Table 7.1) run on symbols, in the conventions of :mod:`cyphy.semantics.dynamics.rigid_body`
(Lynch and Park, *Modern Robotics* ch. 8: twists and wrenches angular part first, ``X`` the
Adjoint that carries the parent's twists into the child frame), with the same transforms
(``dynamics.parent_to_child``).

Why named definitions: written as one expression, ``q̈ = M(q)⁻¹(τ − h(q, q̇))`` grows
exponentially with the depth of the tree, and SymPy's reduction with it (2.1-2.4 s for a
7-link chain, measured; larger trees were refused). Here every intermediate quantity of the
algorithm is a name of its own, defined once from the joint variables and the names before
it: about a hundred short definitions per link, derived in time linear in the number of
links. The arithmetic is a small polynomial type (:class:`Polynomial`), not SymPy's, whose
canonicalisation of every product cost 20 s for a 10-link arm (measured). Per joint, with
``p`` its device prefix (``physmod::joints``: ``p_theta``, ``p_v``, ``p_tau``, ``p_a``) and
``k`` a component (1…6, angular first):

- ``p_V_k``      the body's twist ``V = X·V_parent + S·v`` (pass 1),
- ``p_c_k``      the velocity-product acceleration ``ad(V)·S·v``,
- ``p_IA_j_k``   the articulated inertia ``IA = G + Σ_children Xᵀ·Ia·X`` (symmetric, j ≤ k),
- ``p_pB_k``     the articulated bias wrench ``pB = −ad(V)ᵀ·G·V + Σ_children Xᵀ·pa``,
- ``p_U_k``      ``U = IA·S``, ``p_D`` ``D = Sᵀ·U``, ``p_u`` ``u = τ − Sᵀ·pB``,
- ``p_Ia_j_k``   ``Ia = IA − U·Uᵀ/D`` and ``p_pa_k`` ``pa = pB + Ia·c + U·u/D`` (pass 2),
- ``p_IX_j_k``   ``Ia·X`` (on the way to the parent's ``Xᵀ·Ia·X``),
- ``p_ap_k``     ``a' = X·a_parent + c`` (the root's parent accelerates at ``−g``),
- ``p_qdd``      ``q̈ = (u − Uᵀ·a')/D``, and ``p_dV_k`` ``dV = a' + S·q̈`` (pass 3).

Numbers (zeros, constants) are never named: a quantity's component that has no definition is
a number written where it is used. The recursion is written over the joint's motion
subspace ``S`` (6×nᵢ, :func:`joint_subspace`): the screw axis of a revolute or prismatic
joint as one column of numbers; for a joint of several coordinates (universal, ball, the
floating base: ``dynamics.DOF``) ``S(q)`` depends on the coordinates, its entries named
``p_S_k_c``, and the twist gains the rate of the subspace ``Ṡ·q̇`` (``p_Sdq_k``, in ``c``).
Such a joint has ``p_U_k_c``, ``p_D_a_b`` (symmetric, a ≤ b), ``D⁻¹`` by its adjugate
(``p_det``, ``p_Dinv_a_b``), ``p_u_a`` and ``p_qdd_a``, its coordinates named as
``cyphy solve`` names a vector's components (``Wrist_theta_1``; a floating base's
``<Root>_x`` … and rates ``<Root>_vx`` …, :func:`cyphy.semantics.dynamics.rigid_body.coordinate_names`,
with no effort: nothing drives it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np

from cyphy.model.elements import ElaboratedModel
from cyphy.semantics.dynamics.rigid_body import (STANDARD_GRAVITY, DynamicsError, KinematicTree,
                                      TreeJoint, parent_to_child, port_size, motion_subspace,
                                      motion_subspace_rate, coordinate_names, forward_dynamics,
                                      joint_kind, kinematic_tree)
from cyphy.semantics.scalarise import component_name


@dataclass(frozen=True)
class Definition:
    """``name = value``: ``value`` a polynomial in the joint variables, their cosines and
    sines, the joint efforts and the definitions before it (and their reciprocals);
    ``joint`` the joint (body) whose link the quantity belongs to."""

    name: str
    value: "Polynomial"
    joint: TreeJoint


@dataclass(frozen=True)
class ExplicitMotion:
    """The definitions in order, and per joint (tree order) the names of its accelerations
    (``p_qdd``: one per coordinate)."""

    definitions: tuple[Definition, ...]
    accelerations: tuple[tuple[TreeJoint, tuple[str, ...]], ...]


def subspace(joint: TreeJoint) -> np.ndarray:
    """The joint's motion subspace ``S`` (6×n, child frame): its screw axis as one column,
    without the float noise of the frames (``1.8e-16`` where a rotated axis has a zero)."""
    s = np.asarray(joint.screw, dtype=float).reshape(6, 1)
    return np.where(np.abs(s) < 1e-12 * max(float(np.abs(s).max()), 1e-300), 0.0, s)


def _accumulate(terms: dict[tuple[str, ...], float], key: tuple[str, ...], c: float) -> None:
    """Add ``c`` to the coefficient of ``key``, dropping a term that cancels to zero (so
    that a polynomial's terms are its non-zero ones, and ``is_number`` can trust them)."""
    total = terms.get(key, 0.0) + c
    if total == 0.0:
        terms.pop(key, None)
    else:
        terms[key] = total


class Polynomial:
    """A sum of products ``Σ cₖ·∏ atoms`` with float coefficients: the algorithm's arithmetic
    without SymPy's (whose assumption queries on every product made a 10-link arm take 20 s,
    measured with cProfile). An atom is a name: a symbol, ``cos:q``, ``sin:q`` or ``inv:D``
    (``1/D``). Only products and sums are needed; ``to_sympy`` builds an expression
    once at the end."""

    __slots__ = ("terms",)

    def __init__(self, terms: dict[tuple[str, ...], float] | None = None) -> None:
        self.terms = terms or {}

    @staticmethod
    def atom(name: str) -> "Polynomial":
        return Polynomial({(name,): 1.0})

    @staticmethod
    def lift(value: Any) -> "Polynomial":
        if isinstance(value, Polynomial):
            return value
        number = float(value)
        return Polynomial({(): number} if number != 0.0 else {})

    def is_number(self) -> bool:
        return not self.terms or (len(self.terms) == 1 and () in self.terms)

    def number(self) -> float:
        return self.terms.get((), 0.0)

    def __add__(self, other: Any) -> "Polynomial":
        other = Polynomial.lift(other)
        if not other.terms:
            return self
        terms = dict(self.terms)
        for key, c in other.terms.items():
            _accumulate(terms, key, c)
        return Polynomial(terms)

    __radd__ = __add__

    def __neg__(self) -> "Polynomial":
        return Polynomial({k: -c for k, c in self.terms.items()})

    def __sub__(self, other: Any) -> "Polynomial":
        return self + (-Polynomial.lift(other))

    def __rsub__(self, other: Any) -> "Polynomial":
        return Polynomial.lift(other) + (-self)

    def __mul__(self, other: Any) -> "Polynomial":
        if not isinstance(other, Polynomial):
            number = float(other)
            if number == 0.0:
                return Polynomial()
            return Polynomial({k: c * number for k, c in self.terms.items()})
        terms: dict[tuple[str, ...], float] = {}
        for k1, c1 in self.terms.items():
            for k2, c2 in other.terms.items():
                _accumulate(terms, tuple(sorted(k1 + k2)) if k1 and k2 else k1 or k2, c1 * c2)
        return Polynomial(terms)

    __rmul__ = __mul__

    def atoms(self) -> set[str]:
        """The names it uses (``q`` of ``cos:q``, ``D`` of ``inv:D``)."""
        return {a.partition(":")[2] or a for key in self.terms for a in key}

    def size(self, sizes: dict[str, int]) -> int:
        """Its node count with every name in ``sizes`` written out (that many nodes)."""
        return sum(1 + sum(sizes.get(a.partition(":")[2] or a, 1) for a in key)
                   for key in self.terms) or 1

    def _terms(self, atom: Callable[[str], str], power: str) -> list[tuple[float, str]]:
        out = []
        for key, c in sorted(self.terms.items()):
            up, down = [], []
            for name in sorted(set(key)):
                count = key.count(name)
                kind, _, arg = name.partition(":")
                base = atom(arg) if kind == "inv" else atom(name)
                text = base if count == 1 else f"{base}{power}{count}"
                (down if kind == "inv" else up).append(text)
            body = "*".join(up)
            if down:
                body = (body or "1") + "/" + "/".join(down)
            out.append((c, body))
        return out

    def text(self, atom: Callable[[str], str] | None = None, power: str = "**") -> str:
        """In the notation of ``sympy.sstr`` (``0.5*J0_V_1**2 - cos(J0_theta)/J0_D``),
        coefficients written exactly (``repr`` of the float); ``atom`` prints a name or a
        ``cos:q``/``sin:q`` atom (default: as SymPy does)."""
        atom = atom or _plain_atom
        parts: list[str] = []
        for c, body in self._terms(atom, power):
            magnitude = abs(c)
            if not body:
                term = repr(magnitude)
            elif magnitude == 1.0:
                term = body
            else:
                term = f"{repr(magnitude)}*{body}"
            if not parts:
                parts.append(f"-{term}" if c < 0 else term)
            else:
                parts.append(f" - {term}" if c < 0 else f" + {term}")
        return "".join(parts) or "0"

    def to_sympy(self, symbols: dict[str, Any]) -> Any:
        """The SymPy expression (``symbols``: name → SymPy value, filled with real symbols
        for the names not in it)."""
        import sympy

        def atom(name: str) -> Any:
            kind, _, arg = name.partition(":")
            if not arg:
                if name not in symbols:
                    symbols[name] = sympy.Symbol(name, real=True)
                return symbols[name]
            inner = atom(arg)
            return {"cos": sympy.cos, "sin": sympy.sin}[kind](inner) if kind != "inv" \
                else 1 / inner

        total = sympy.Integer(0)
        for key, c in self.terms.items():
            term = sympy.Float(c) if c != 1.0 else sympy.Integer(1)
            for name in key:
                term = term * atom(name)
            total = total + term
        return total

    def trig_reduced(self) -> "Polynomial":
        """With ``sin²q`` written ``1 − cos²q`` until no term holds a sine twice: the
        transforms' products of rotations then collect (``cos³q + cos q·sin²q`` is
        ``cos q``)."""
        out = Polynomial()
        for key, c in self.terms.items():
            term = Polynomial({(): c})
            for name in sorted(set(key)):
                count = key.count(name)
                if name.startswith("sin:") and count >= 2:
                    cos = Polynomial.atom("cos:" + name[4:])
                    factor = Polynomial.lift(1.0)
                    for _ in range(count // 2):
                        factor = factor * (1.0 - cos * cos)
                    if count % 2:
                        factor = factor * Polynomial.atom(name)
                    term = term * factor
                else:
                    term = term * Polynomial({(name,) * count: 1.0})
            out = out + term
        return out

    def to_expr(self) -> Any:
        """As the shared expression AST (``cyphy.expr``): a sum of products, coefficients as
        decimal numbers (``repr`` of the float), ``cos``/``sin`` calls, ``1/D`` a division."""
        from cyphy import expr as ex

        def atom(name: str) -> ex.Expr:
            kind, _, arg = name.partition(":")
            if not arg:
                return ex.Name((name,))
            return ex.Call(ex.Name((kind,)), (ex.Name((arg,)),))

        out: ex.Expr | None = None
        for key, c in sorted(self.terms.items()):
            up = [atom(a) for a in key if not a.startswith("inv:")]
            down = [atom(a[4:]) for a in key if a.startswith("inv:")]
            magnitude = abs(c)
            number = str(int(magnitude)) if magnitude.is_integer() and magnitude < 1e15 \
                else repr(magnitude)
            factors = ([ex.Num(number)] if magnitude != 1.0 or not up else []) + up
            term = factors[0]
            for f in factors[1:]:
                term = ex.BinOp("*", term, f)
            for d in down:
                term = ex.BinOp("/", term, d)
            if out is None:
                out = ex.UnaryOp("-", term) if c < 0 else term
            else:
                out = ex.BinOp("-" if c < 0 else "+", out, term)
        return out if out is not None else ex.Num("0")

    def chopped(self, relative: float = 1e-12, absolute: float = 1e-15) -> "Polynomial":
        """Without float noise (``1e-17·cos q`` where a term of a transform cancels)."""
        if not self.terms:
            return self
        limit = max(relative * max(abs(c) for c in self.terms.values()), absolute)
        return Polynomial({k: c for k, c in self.terms.items() if abs(c) >= limit})


def _plain_atom(name: str) -> str:
    kind, _, arg = name.partition(":")
    return f"{kind}({arg})" if arg else name


def _cos(q: Polynomial) -> Polynomial:
    return Polynomial.atom(f"cos:{_single(q)}")


def _sin(q: Polynomial) -> Polynomial:
    return Polynomial.atom(f"sin:{_single(q)}")


def _single(q: Polynomial) -> str:
    [(key, coefficient)] = q.terms.items()
    assert coefficient == 1.0 and len(key) == 1, "a joint coordinate is one symbol"
    return key[0]


class _Namer:
    """Collects definitions; a value that is a number is used as it is (so a component
    that is not defined is a number: zero for a twist's)."""

    def __init__(self) -> None:
        self.definitions: list[tuple[str, Polynomial, TreeJoint]] = []

    def __call__(self, name: str, value: Any, joint: TreeJoint, always: bool = False) -> Any:
        value = Polynomial.lift(value)
        if not always and value.is_number():
            return value
        self.definitions.append((name, value, joint))
        return Polynomial.atom(name)


def _dot(row: Sequence[Any], column: Sequence[Any]) -> Any:
    """``Σ rowₖ·columnₖ`` skipping exact zeros."""
    total: Any = Polynomial()
    for a, b in zip(row, column):
        if _zero(a) or _zero(b):
            continue
        total = total + a * b
    return total


def _zero(value: Any) -> bool:
    if isinstance(value, Polynomial):
        return not value.terms
    return float(value) == 0.0


def _matvec(m: Any, v: Sequence[Any]) -> list[Any]:
    return [_dot(m[i], v) for i in range(len(m))]


def _tmatvec(m: Any, v: Sequence[Any]) -> list[Any]:
    """``mᵀ·v``."""
    return [_dot([m[k][j] for k in range(len(m))], v) for j in range(len(m[0]))]


def _cross(a: Sequence[Any], b: Sequence[Any]) -> list[Any]:
    return [_dot([a[1], -a[2]], [b[2], b[1]]),
            _dot([a[2], -a[0]], [b[0], b[2]]),
            _dot([a[0], -a[1]], [b[1], b[0]])]


def _cross_motion(v: Sequence[Any], w: Sequence[Any]) -> list[Any]:
    """``ad(v)·w`` for twists (angular first): ``(ω×ω', ω×v' + v×ω')``."""
    top = _cross(v[:3], w[:3])
    bottom = [x + y for x, y in zip(_cross(v[:3], w[3:]), _cross(v[3:], w[:3]))]
    return top + bottom


def _cross_force(v: Sequence[Any], f: Sequence[Any]) -> list[Any]:
    """``−ad(v)ᵀ·f`` for a twist ``v`` and a wrench ``f`` (angular first):
    ``(ω×m + v×f_lin, ω×f_lin)``."""
    top = [x + y for x, y in zip(_cross(v[:3], f[:3]), _cross(v[3:], f[3:]))]
    return top + _cross(v[:3], f[3:])


def explicit_motion(tree: KinematicTree, variables: Callable[[TreeJoint, str], Any]
                    ) -> ExplicitMotion:
    """The articulated-body algorithm on symbols: ``variables(joint, port)`` names a joint's
    ``theta``, ``v`` or ``tau`` (a list of names for a joint of several coordinates; an
    empty ``tau`` list: no effort, as for a floating base). Cost and size linear in the
    number of joints (a bounded number of short definitions per link)."""
    name = _Namer()
    n = len(tree)

    def coordinates(joint: TreeJoint, port: str) -> list[Polynomial]:
        found = variables(joint, port)
        names = [found] if isinstance(found, str) else list(found)
        if port == "tau" and not names:
            return [Polynomial()] * joint.dof
        assert len(names) == joint.dof, f"{joint.name}: {joint.dof} coordinates, {names}"
        return [Polynomial.atom(x) for x in names]

    # Pass 1: root to leaves, subspaces, twists and velocity-product accelerations
    xs: list[list[list[Any]]] = []
    subspaces: list[list[list[Any]]] = []  # S, 6 rows of dof columns
    twists: list[list[Any]] = []
    products: list[list[Any]] = []  # c = ad(V)·S·q̇ (+ Ṡ·q̇)
    for i, joint in enumerate(tree.joints):
        p = joint.prefix
        q = coordinates(joint, "theta")
        qd = coordinates(joint, "v")
        raw = parent_to_child(joint, q[0] if len(q) == 1 else q, _cos, _sin)
        xs.append([[_clean(raw[r, k]) for k in range(6)] for r in range(6)])
        s, rate = joint_subspace(joint, q, qd, name)
        subspaces.append(s)
        motion = [_dot(s[r], qd) for r in range(6)]
        v = _matvec(xs[i], twists[joint.parent]) if joint.parent >= 0 else [0.0] * 6
        v = [name(f"{p}_V_{k + 1}", v[k] + motion[k], joint) for k in range(6)]
        twists.append(v)
        c = _cross_motion(v, motion)
        products.append([name(f"{p}_c_{k + 1}", c[k] + rate[k], joint) for k in range(6)])

    # Pass 2: leaves to root; a child's articulated inertia and bias are added to its
    # parent's once the child is complete (tree order puts every child after its parent)
    extra_inertia: list[list[list[Any]]] = [[[0.0] * 6 for _ in range(6)] for _ in range(n)]
    extra_bias: list[list[Any]] = [[0.0] * 6 for _ in range(n)]
    us: list[Any] = [None] * n
    d_invs: list[Any] = [None] * n
    efforts: list[Any] = [None] * n
    for i in range(n - 1, -1, -1):
        joint = tree.joints[i]
        p, s = joint.prefix, subspaces[i]
        columns = joint.dof
        column = [[s[k][c] for k in range(6)] for c in range(columns)]
        scale = 1e-14 * float(np.abs(joint.inertia).max())  # float noise of the frames
        g = [[float(x) if abs(x) >= scale else 0.0 for x in row] for row in joint.inertia]
        bias = _cross_force(twists[i], _matvec(g, twists[i]))
        ia: list[list[Any]] = [[None] * 6 for _ in range(6)]
        for r in range(6):
            for k in range(r, 6):
                ia[r][k] = ia[k][r] = name(f"{p}_IA_{r + 1}_{k + 1}",
                                           extra_inertia[i][r][k] + g[r][k], joint)
        pa = [name(f"{p}_pB_{k + 1}", bias[k] + extra_bias[i][k], joint) for k in range(6)]
        tag = (lambda c: "") if columns == 1 else (lambda c: f"_{c + 1}")
        u_mat = [[name(f"{p}_U_{k + 1}{tag(c)}", _dot(ia[k], column[c]), joint)
                  for c in range(columns)] for k in range(6)]
        tau = coordinates(joint, "tau")
        if columns == 1:
            d = name(f"{p}_D", _dot(column[0], [u_mat[k][0] for k in range(6)]), joint,
                     always=True)
            d_inv = [[Polynomial.atom(f"inv:{_single(d)}")]]
            u = [name(f"{p}_u", tau[0] - _dot(column[0], pa), joint)]
        else:  # several coordinates: D (at most 6×6, symmetric) inverted by its adjugate
            d_m: list[list[Any]] = [[None] * columns for _ in range(columns)]
            for a in range(columns):
                for b in range(a, columns):
                    d_m[a][b] = d_m[b][a] = name(
                        f"{p}_D_{a + 1}_{b + 1}",
                        _dot(column[a], [u_mat[k][b] for k in range(6)]), joint)
            adjugate, det = _adjugate(d_m)
            inv_det = Polynomial.atom(f"inv:{_single(name(f'{p}_det', det, joint, always=True))}")
            d_inv = [[None] * columns for _ in range(columns)]
            for a in range(columns):
                for b in range(a, columns):
                    d_inv[a][b] = d_inv[b][a] = name(f"{p}_Dinv_{a + 1}_{b + 1}",
                                                     adjugate[a][b] * inv_det, joint)
            u = [name(f"{p}_u_{a + 1}", tau[a] - _dot(column[a], pa), joint)
                 for a in range(columns)]
        us[i], d_invs[i], efforts[i] = u_mat, d_inv, u
        if joint.parent < 0:
            continue
        # Ia = IA − U·D⁻¹·Uᵀ,  pa = pB + Ia·c + U·D⁻¹·u
        ud = [[_dot(u_mat[k], [d_inv[a][b] for a in range(columns)]) for b in range(columns)]
              for k in range(6)]
        small: list[list[Any]] = [[None] * 6 for _ in range(6)]
        for r in range(6):
            for k in range(r, 6):
                small[r][k] = small[k][r] = name(
                    f"{p}_Ia_{r + 1}_{k + 1}", ia[r][k] - _dot(ud[r], u_mat[k]), joint)
        ic = _matvec(small, products[i])
        pa_small = [name(f"{p}_pa_{k + 1}", pa[k] + ic[k] + _dot(ud[k], u), joint)
                    for k in range(6)]
        # the parent's share Xᵀ·Ia·X and Xᵀ·pa, through IX = Ia·X
        x = xs[i]
        ix = [[name(f"{p}_IX_{r + 1}_{k + 1}", _dot(small[r], [x[m][k] for m in range(6)]),
                    joint) for k in range(6)] for r in range(6)]
        target, wrench = extra_inertia[joint.parent], extra_bias[joint.parent]
        for r in range(6):
            for k in range(r, 6):
                target[r][k] = target[r][k] + _dot([x[m][r] for m in range(6)],
                                                   [ix[m][k] for m in range(6)])
        moved = _tmatvec(x, pa_small)
        for k in range(6):
            wrench[k] = wrench[k] + moved[k]

    # Pass 3: root to leaves, the accelerations (the root's parent accelerates at −g)
    gravity = [0.0, 0.0, 0.0] + [-float(g) for g in tree.gravity]
    accelerations: list[list[Any]] = []
    out: list[tuple[TreeJoint, tuple[str, ...]]] = []
    for i, joint in enumerate(tree.joints):
        p, s = joint.prefix, subspaces[i]
        columns = joint.dof
        parent = accelerations[joint.parent] if joint.parent >= 0 else gravity
        moved = _matvec(xs[i], parent)
        ap = [name(f"{p}_ap_{k + 1}", moved[k] + products[i][k], joint) for k in range(6)]
        rest = [efforts[i][a] - _dot([us[i][k][a] for k in range(6)], ap)
                for a in range(columns)]
        names = [f"{p}_qdd" if columns == 1 else f"{p}_qdd_{a + 1}" for a in range(columns)]
        qdd = [name(names[a], _dot(d_invs[i][a], rest), joint, always=True)
               for a in range(columns)]
        out.append((joint, tuple(names)))
        step = [_dot(s[k], qdd) for k in range(6)]
        accelerations.append([name(f"{p}_dV_{k + 1}", ap[k] + step[k], joint)
                              for k in range(6)])
    definitions = tuple(Definition(key, value, joint) for key, value, joint in name.definitions)
    return ExplicitMotion(definitions, tuple(out))


def _clean(value: Any) -> Any:
    """An entry of a transform or subspace as a polynomial without float noise, its
    products of rotations collected."""
    return Polynomial.lift(value).trig_reduced().chopped()


def joint_subspace(joint: TreeJoint, q: Sequence[Polynomial], qd: Sequence[Polynomial],
                   name: Callable[..., Any]) -> tuple[list[list[Any]], list[Any]]:
    """``(S, Ṡ·q̇)`` of the joint at coordinates ``q`` and rates ``qd`` (6 rows of ``dof``
    columns, and a 6-vector): numbers for one coordinate (:func:`subspace`, no rate); for
    several, ``dynamics.motion_subspace`` and ``motion_subspace_rate`` on symbols, each entry that is
    not a number named (``p_S_k_c``, ``p_Sdq_k``) through ``name``."""
    if joint.dof == 1:
        return [[float(x) for x in row] for row in subspace(joint)], [0.0] * 6
    p = joint.prefix
    raw = motion_subspace(joint, list(q), _cos, _sin)
    s = [[name(f"{p}_S_{k + 1}_{c + 1}", _clean(raw[k, c]), joint)
          for c in range(joint.dof)] for k in range(6)]
    rate = motion_subspace_rate(joint, list(q), list(qd), _cos, _sin)
    return s, [name(f"{p}_Sdq_{k + 1}", _clean(rate[k]), joint) for k in range(6)]


def _adjugate(m: list[list[Any]]) -> tuple[list[list[Any]], Any]:
    """The adjugate and the determinant of a small square matrix of ``Polynomial`` (Laplace
    expansion along the first row, minors memoised)."""
    size = len(m)
    memo: dict[tuple[tuple[int, ...], tuple[int, ...]], Any] = {}

    def det(rows: tuple[int, ...], cols: tuple[int, ...]) -> Any:
        if not rows:
            return Polynomial.lift(1.0)
        key = (rows, cols)
        if key not in memo:
            total: Any = Polynomial()
            for j, c in enumerate(cols):
                if _zero(m[rows[0]][c]):
                    continue
                minor = det(rows[1:], cols[:j] + cols[j + 1:])
                total = total + (m[rows[0]][c] * minor) * (-1.0 if j % 2 else 1.0)
            memo[key] = total
        return memo[key]

    everything = tuple(range(size))
    adjugate = [[det(tuple(r for r in everything if r != b),
                     tuple(c for c in everything if c != a)) * (-1.0 if (a + b) % 2 else 1.0)
                 for b in range(size)] for a in range(size)]
    return adjugate, det(everything, everything)


_JOINT_PORTS = ("theta", "v", "a", "tau")


def model_motion(model: ElaboratedModel, gravity: Sequence[float] = STANDARD_GRAVITY,
                 floating_base: bool = False) -> ExplicitMotion | None:
    """The explicit accelerations of the model's kinematic tree in its joints' own variables
    (``physmod::joints``: ``<J>_theta``, ``<J>_v``, ``<J>_tau``; ``<J>_a == <J>_qdd``; a joint
    of several coordinates has vector ports, named by component, ``<J>_theta_1`` …), the
    root fixed to the world or, with ``floating_base``, free (its coordinates ``<Root>_x`` …
    are new variables, :func:`cyphy.semantics.dynamics.rigid_body.coordinate_names`). None when the
    tree has no moving joint, or when a joint's definition lacks one of these variables
    (nothing here can name its motion). Raises ``DynamicsError`` for a tree without
    equations of motion (a singular mass matrix included: the numeric algorithm checks it
    at ``q = 0``) and for a joint whose variables do not have its number of coordinates."""
    moving = [j for j in model.joints if j.parent is not None and j.child is not None
              and joint_kind(j) != "fixed"]
    if not moving and not floating_base:
        return None
    for joint in moving:  # before the tree: a model whose joints cannot say it is left alone
        if joint.device is None or any(joint.device.port(p) is None for p in _JOINT_PORTS):
            return None
    tree = kinematic_tree(model, gravity, floating_base)
    if not len(tree):
        return None
    zero = [0.0] * tree.dof
    forward_dynamics(tree, zero, zero, zero)

    def port(joint: TreeJoint, name: str) -> Any:
        if joint.kind == "floating":
            return coordinate_names(joint, name)
        found = joint.element.device.port(name)  # type: ignore[union-attr]
        size = port_size(found.type)
        if (joint.dof == 1) != (size is None) or (size is not None and size != joint.dof):
            raise DynamicsError(
                f"joint {joint.name} has {joint.dof} coordinate"
                f"{'s' if joint.dof > 1 else ''}, but its variable {name} is not "
                + ("a scalar" if joint.dof == 1 else f"a vector of {joint.dof}"),
                joint.element.span, f"declare {name}: " + (
                    "real" if joint.dof == 1 else f"vector(real, {joint.dof})"))
        if joint.dof == 1:
            return found.mangled
        return [component_name(found.mangled, k) for k in range(joint.dof)]

    return explicit_motion(tree, port)
