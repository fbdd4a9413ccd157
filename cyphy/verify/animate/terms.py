"""Values of the theory's terms (trees of ``utp_terms.lark``), numeric or symbolic.

One evaluator serves both uses: given floats it computes a value (a condition, an event's
argument, an assignment), given SymPy symbols for the state it builds ``Evolve``'s equations.
The operators are Python's, so the same code is right for both; the few HOL functions the
printer emits map onto :mod:`math` or SymPy by the operands' kind."""

from __future__ import annotations

import math
from typing import Any, Callable

from cyphy.verify.animate.errors import AnimateError

Lookup = Callable[[str], Any]

_ARITH: dict[str, Callable[[Any, Any], Any]] = {
    "+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
    "/": lambda a, b: a / b, "^": lambda a, b: a ** b, "powr": lambda a, b: a ** b,
    "@": lambda a, b: list(a) + list(b),
}
_COMPARE: dict[str, Callable[[Any, Any], Any]] = {
    "=": lambda a, b: a == b, "\\<noteq>": lambda a, b: a != b, "<": lambda a, b: a < b,
    ">": lambda a, b: a > b, "\\<le>": lambda a, b: a <= b, "\\<ge>": lambda a, b: a >= b,
    "\\<and>": lambda a, b: bool(a) and bool(b), "\\<or>": lambda a, b: bool(a) or bool(b),
    "\\<longrightarrow>": lambda a, b: (not a) or bool(b),
    "\\<longleftrightarrow>": lambda a, b: bool(a) == bool(b),
    "\\<Rightarrow>": lambda a, b: (not a) or bool(b),
    "\\<Leftrightarrow>": lambda a, b: bool(a) == bool(b),
}
_FUNCTIONS = ("sin", "cos", "tan", "sqrt", "exp", "ln", "abs", "arctan", "real", "nat",
              "of_nat", "real_of_int", "of_int", "floor", "ceiling")


class Unsupported(Exception):
    """A node the evaluator does not know (the caller adds the place)."""


def op_name(token: Any) -> str:
    """The operator of a ``binop``: ``=\\<^sub>u`` → ``=``, a holop tree → its symbol."""
    text = str(token.children[0]) if hasattr(token, "children") else str(token)
    return text.replace("\\<^sub>u", "")


def _function(name: str, args: list[Any]) -> Any:
    if name in ("real", "of_nat", "nat", "real_of_int", "of_int"):  # embeddings in the reals
        return args[0]
    symbolic = any(hasattr(a, "free_symbols") for a in args)
    if symbolic:
        import sympy  # lazy: only Evolve's equations are symbolic
        table = {"sin": sympy.sin, "cos": sympy.cos, "tan": sympy.tan, "sqrt": sympy.sqrt,
                 "exp": sympy.exp, "ln": sympy.log, "abs": sympy.Abs, "arctan": sympy.atan,
                 "floor": sympy.floor, "ceiling": sympy.ceiling}
    else:
        table = {"sin": math.sin, "cos": math.cos, "tan": math.tan, "sqrt": math.sqrt,
                 "exp": math.exp, "ln": math.log, "abs": abs, "arctan": math.atan,
                 "floor": math.floor, "ceiling": math.ceil}
    if name not in table:
        raise Unsupported(f"the function {name}")
    return table[name](*args)


def evaluate_hol(node: Any, name: Lookup) -> Any:
    """A HOL term's value; ``name`` gives a constant's or a bound name's."""
    return evaluate(node, _no_state, _no_state, name)


def _no_state(var: str) -> Any:
    raise Unsupported(f"the state variable {var} in a HOL term")


def evaluate(node: Any, state: Lookup, derivative: Lookup, name: Lookup) -> Any:
    """The value of a uexpr or hol tree: ``state`` reads ``&x``/``$x``, ``derivative``
    ``$x\\<acute>``, ``name`` the constants and bound names inside ``\\<guillemotleft>…»``."""
    kind = node.data if hasattr(node, "data") else None
    ch = getattr(node, "children", [])

    def ev(n: Any) -> Any:
        return evaluate(n, state, derivative, name)

    if kind in ("state", "state_in"):
        return state(str(ch[0]))
    if kind == "state_derivative":
        return derivative(str(ch[0]))
    if kind == "lifted":
        return ev(ch[0])
    if kind == "number":
        text = str(ch[0])
        return float(text) if "." in text else int(text)
    if kind in ("utrue", "true"):
        return True
    if kind in ("ufalse", "false"):
        return False
    if kind == "name":
        return name(str(ch[0]))
    if kind == "binop":
        op = op_name(ch[1])
        left, right = ev(ch[0]), ev(ch[2])
        if op in _ARITH:
            return _ARITH[op](left, right)
        if op in _COMPARE:
            return _COMPARE[op](left, right)
        raise Unsupported(f"the operator {op}")
    if kind == "conj_u":
        return bool(ev(ch[0])) and bool(ev(ch[1]))
    if kind == "neg":
        return -ev(ch[0])
    if kind == "not_":
        return not ev(ch[0])
    if kind == "fmod":
        a, b = ev(ch[0]), ev(ch[1])
        return math.fmod(a, b)
    if kind == "tuple":
        return tuple(ev(c) for c in ch)
    if kind == "sequence":
        return [ev(c) for c in ch if c is not None]
    if kind == "index":
        return ev(ch[0])[int(str(ch[1]))]
    if kind == "apply":
        return _function(str(ch[0]), [ev(c) for c in ch[1:]])
    if kind == "lifted_call":
        return _function(str(ch[1]), [ev(c) for c in ch[2:]])
    if kind == "lifted_binop":
        op = op_name(ch[1])
        left, right = ev(ch[2]), ev(ch[3])
        return (_ARITH.get(op) or _COMPARE[op])(left, right)
    raise Unsupported(f"the term {kind or node}")


def place(err: Unsupported, definition: Any) -> AnimateError:
    """The reader's diagnostic for an unsupported node met in ``definition``."""
    return AnimateError("E-ANIMATE-UNSUPPORTED", f"{definition.name}: animate does not run "
                        f"{err}", path=definition.path, line=definition.line, status=2)
