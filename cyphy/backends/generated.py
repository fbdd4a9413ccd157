"""Python functions generated from a reduced model's expressions and named definitions, for
``cyphy simulate`` (issues 16 and 31).

The definitions are a tree's equations of motion (articulated-body polynomials, about a
hundred per link) and the algebraic quantities they use (SymPy values). A function here
computes only the definitions its results need (:func:`needed`), in order, one assignment
each, so that a whole model whose tree Pinocchio evaluates does not compute the symbolic
tree at every step, and a state Jacobian is generated from its non-zero entries alone
(:func:`sparse_jacobian`): a chain of 50 links with a motor per joint has 250 states and
about 1,200 non-zero entries among 62,500.
"""

from __future__ import annotations

import math
from typing import Any, Callable, Collection, Sequence

import numpy as np


def uses(value: Any) -> set[str]:
    """The names a definition's value uses (a SymPy value or an articulated-body
    polynomial)."""
    if hasattr(value, "free_symbols"):
        return {str(x) for x in value.free_symbols}
    return set(value.atoms())


def definition_names(definitions: Sequence[tuple[str, Any]]) -> set[str]:
    """The names the definitions use."""
    out: set[str] = set()
    for _, value in definitions:
        out |= uses(value)
    return out


def needed(definitions: Sequence[tuple[str, Any]], roots: Collection[str],
           given: Collection[str]) -> list[tuple[str, Any]]:
    """The definitions that ``roots`` need (transitively), in their order, without those
    ``given`` (arguments of the function: what it does not compute)."""
    want, given = set(roots), set(given)
    for name, value in reversed(definitions):
        if name in want and name not in given:
            want |= uses(value)
    return [(n, v) for n, v in definitions if n in want and n not in given]


def compiled(args: Sequence[str], definitions: Sequence[tuple[str, Any]],
             *results: Sequence[Any]) -> list[Callable[..., list[float]]]:
    """Per list of ``results``, a Python function of ``args`` that computes the definitions
    in order (one assignment each: a tree's equations of motion stay linear in its size) and
    returns those expressions. Generated as source, as ``lambdify`` does, with ``math`` for
    the functions (each cosine and sine of a joint angle computed once) and every name
    prefixed (``v_``), so that no model name can clash with Python's."""
    # lazy: SymPy is not needed by `cyphy check`
    import sympy
    from sympy.printing.pycode import PythonCodePrinter  # lazy: SymPy (see above)

    printer = PythonCodePrinter({"fully_qualified_modules": True})

    def code(value: Any) -> str:
        if not hasattr(value, "free_symbols"):  # an articulated-body polynomial
            return value.text(_python_atom)
        value = sympy.sympify(value)
        return printer.doprint(value.xreplace(
            {s: sympy.Symbol(f"v_{s.name}", real=True) for s in value.free_symbols}))

    trig = sorted({a for _, value in definitions if not hasattr(value, "free_symbols")
                   for key in value.terms for a in key if a[:4] in ("cos:", "sin:")})
    body = [f"    {_python_atom(a)} = math.{a[:3]}(v_{a[4:]})" for a in trig]
    body += [f"    v_{name} = {code(value)}" for name, value in definitions]
    # one function returns every list (compiling the definitions is most of the cost of
    # building it: 0.1 s for a 10-link arm's thousand, measured); each result picks its own
    lists = ", ".join(f"[{', '.join(code(e) for e in exprs)}]" for exprs in results)
    lines = [f"def _generated({', '.join(f'v_{a}' for a in args)}):", *body,
             f"    return ({lists},)"]
    namespace: dict[str, Any] = {"math": math}
    exec(compile("\n".join(lines), "<cyphy simulate>", "exec"), namespace)  # noqa: S102
    generated = namespace["_generated"]
    return [(lambda *values, k=k: generated(*values)[k]) for k in range(len(results))]


def _python_atom(name: str) -> str:
    """``v_x`` for a name, ``cos_x`` for ``cos:x`` (computed once, at the top)."""
    kind, _, arg = name.partition(":")
    return f"{kind}_{arg}" if arg else f"v_{name}"


def sparse_jacobian(args: Sequence[str], exprs: Sequence[Any], wrt: Sequence[str]
                    ) -> Callable[..., np.ndarray]:
    """``∂exprs/∂wrt`` (SymPy expressions of ``args``, no definitions) as a function of
    ``args`` that returns the dense ``len(exprs) × len(wrt)`` matrix: each expression is
    differentiated by the names it uses only, and the non-zero entries are generated as one
    function, so that the cost follows the entries, not the matrix."""
    # lazy: SymPy is not needed by `cyphy check`
    import sympy

    column = {name: k for k, name in enumerate(wrt)}
    rows: list[int] = []
    cols: list[int] = []
    entries: list[Any] = []
    for i, e in enumerate(exprs):
        e = sympy.sympify(e)
        for s in sorted(e.free_symbols, key=str):
            j = column.get(str(s))
            if j is None:
                continue
            d = sympy.diff(e, s)
            if d != 0:
                rows.append(i)
                cols.append(j)
                entries.append(d)
    shape = (len(exprs), len(wrt))
    if not entries:
        return lambda *_values: np.zeros(shape)
    try:  # Python's printer: fast to build (lambdify's renaming took 6 s for 1,200 entries)
        (values,) = compiled(args, [], entries)
    except (TypeError, ValueError, NotImplementedError):  # a function it cannot print
        values = lambdified(args, entries)
    at = (np.array(rows, dtype=int), np.array(cols, dtype=int))

    def jacobian(*arguments: float) -> np.ndarray:
        out = np.zeros(shape)
        out[at] = values(*arguments)
        return out

    return jacobian


def lambdified(args: Sequence[str], exprs: Sequence[Any]) -> Callable[..., list[Any]]:
    """``exprs`` (SymPy, no definitions) as one NumPy function of the names ``args``:
    ``lambdify`` knows more functions than Python's printer (``Heaviside``, ``sign``)."""
    # lazy: SymPy is not needed by `cyphy check`
    import sympy

    found = {str(s): s for e in exprs for s in sympy.sympify(e).free_symbols}
    symbols = [found.get(n, sympy.Symbol(n, real=True)) for n in args]
    return sympy.lambdify(symbols, list(exprs), "numpy")
