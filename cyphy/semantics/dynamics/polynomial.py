"""The arithmetic of the articulated-body definitions (:mod:`cyphy.semantics.dynamics.articulated`):
a small polynomial type over names, cosines, sines and reciprocals of names, with float
coefficients, and the sums of products the recursion needs. Kept apart from SymPy, whose
assumption queries on every product made a 10-link arm take 20 s (measured with cProfile)."""

from __future__ import annotations

from typing import Any, Callable, Sequence
from cyphy import expr as ex


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
        import sympy  # lazy: SymPy (0.5-1 s); only the symbolic form needs it

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
