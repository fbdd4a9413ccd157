"""The scalarisation pass (cyphy.semantics.scalarise): shapes inferred, mismatches refused
with the node, component equations named as ``cyphy solve`` names components, and the
p-model process with scalar state, evolving locals promoted and set-points held."""

from __future__ import annotations

import pytest

from conftest import EXAMPLES
from cyphy import api
from cyphy import expr as ex
from cyphy.lang.notation import to_notation
from cyphy.semantics.circus import ast as c
from cyphy.semantics.scalarise.process import scalar_process
from cyphy.semantics.scalarise.scalariser import Scalariser
from cyphy.semantics.scalarise.shapes import ScalariseError


def N(text: str) -> ex.Name:
    return ex.Name((text,))


SC = Scalariser({"F": (6,), "A": (6,), "fV": (6,), "pV": (6,), "M": (3, 4), "Q": (4, 3),
                 "R": (3, 3), "v3": (3,)}, frozenset({"F", "fV", "pV", "R"}))


def texts(p: ex.Expr) -> list[str]:
    return [to_notation(q) for q in SC.predicate(p)]


def test_vector_equation_is_one_equation_per_component() -> None:
    eq = ex.BinOp("==", N("fV"), ex.BinOp("+", N("pV"), ex.BinOp("*", N("A"), N("v"))))
    assert texts(eq) == [f"fV_{k + 1} == pV_{k + 1} + A[{k}] * v" for k in range(6)]


def test_transpose_product_is_the_sum_of_component_products() -> None:
    eq = ex.BinOp("==", N("tau"), ex.BinOp("*", ex.Call(N("transpose"), (N("F"),)), N("A")))
    assert texts(eq) == [" + ".join(f"F_{k + 1} * A[{k}]" for k in range(6)).join(
        ["tau == ", ""])]


def test_matrix_product_components_sum_over_the_inner_index() -> None:
    eq = ex.BinOp("==", N("R"), ex.BinOp("*", N("M"), N("Q")))
    got = texts(eq)
    assert len(got) == 9
    assert got[5] == "R_6 == " + " + ".join(f"M[1, {k}] * Q[{k}, 2]" for k in range(4))


def test_scalar_equations_pass_unchanged() -> None:
    eq = ex.BinOp("==", ex.Derivative(N("theta")), N("v"))
    assert SC.predicate(eq) == [eq]
    assert SC.predicate(eq)[0] is eq


@pytest.mark.parametrize("expr, message", [
    (ex.BinOp("==", N("M"), N("Q")), "an equation between a 3x4 matrix and a 4x3 matrix"),
    (ex.BinOp("==", N("F"), N("v3")), "an equation between a 6-vector and a 3-vector"),
    (ex.BinOp("==", N("R"), ex.BinOp("*", N("M"), N("M"))),
     "product of a 3x4 matrix and a 3x4 matrix: the left's 4 columns are not the right's 3"),
    (ex.BinOp("==", N("F"), ex.BinOp("+", N("F"), N("v3"))),
     "'+' between a 6-vector and a 3-vector"),
    (ex.BinOp("==", N("x"), ex.Call(N("sin"), (N("F"),))), "sin applied to a vector"),
    (ex.BinOp("<", N("F"), N("x")), "'<' on a 6-vector"),
])
def test_shape_mismatch_is_refused_with_its_node(expr: ex.Expr, message: str) -> None:
    with pytest.raises(ScalariseError) as err:
        SC.predicate(expr)
    assert message in str(err.value)


def test_unsized_vector_is_refused_but_its_items_are_read() -> None:
    sc = Scalariser({}, frozenset(), frozenset({"X"}))
    with pytest.raises(ScalariseError, match="size is not declared"):
        sc.predicate(ex.BinOp("==", N("X"), N("X")))
    item = ex.Index(N("X"), (ex.Num("2"),))
    assert sc.predicate(ex.BinOp("==", N("y"), item)) == [
        ex.BinOp("==", N("y"), ex.Index(N("X"), (ex.Num("1"),)))]


def test_dcmotor_process_is_scalar_with_evolving_locals_as_state() -> None:
    checked, built = api.semantics([EXAMPLES / "dcmotor"])
    assert built is not None
    scalar = scalar_process(built.program.pmodel)
    pm = scalar.process
    state = {f.name: f for f in pm.state.fields}
    assert all(f.type == c.REAL or f.type == c.BOOL for f in pm.state.fields)
    assert {f"Shaft_fA_{k}" for k in range(1, 7)} <= set(state)
    assert "Shaft_fA" not in state
    assert state["Shaft_fA_3"].visible and not state["Shaft_pA_3"].visible
    # locals whose derivative appears, and the integral, are state; the others stay local
    assert set(scalar.promoted) == {"Shaft_theta", "Shaft_v", "Motor_i", "Motor_theta",
                                    "Motor_av", "Motor_e", "Motor_e_int"}
    assert {f.name for f in pm.local.fields} == {"Shaft_a", "Motor_Tm", "Motor_Vemf",
                                                 "Motor_Tf", "Motor_V"}
    assert scalar.held == ("Motor_das",)
    [evolve] = [d.body for d in pm.actions if isinstance(d.body, c.Evolution)]
    eqs = {to_notation(e) for e in evolve.equations}
    assert "derivative(Motor_das) == 0" in eqs
    assert "derivative(Motor_e_int) == Motor_e" in eqs
    # ad(fV) * A * v written out: row 3 of ad(fV) is (-fV_2, fV_1, 0, 0, 0, 0)
    assert ("Shaft_fA_3 == Shaft_pA_3 + (-Shaft_fV_2 * Shaft_A[0] + Shaft_fV_1 * Shaft_A[1])"
            " * Shaft_v + Shaft_A[2] * Shaft_a") in eqs
    assert not any(isinstance(n, ex.Integral) for e in evolve.equations for n in e.walk())


# ---------------------------------------------------------------- against NumPy

import numpy as np  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

SHAPES = {"x": (3,), "y": (3,), "z": (2,), "M": (2, 3), "N": (3, 3), "K": (3, 2)}
SPLIT = frozenset({"x", "z", "M", "K"})  # variables split into x_1…; y and N stay indexed


def evaluate(e: ex.Expr, env: dict[str, object]) -> float:
    """A scalar expression of the pass's output, evaluated (components and indices)."""
    if isinstance(e, ex.Num):
        return float(e.text)
    if isinstance(e, ex.Name):
        return float(env[e.text])  # type: ignore[arg-type]
    if isinstance(e, ex.Index):
        value = np.asarray(env[e.base.text])  # type: ignore[union-attr]
        return float(value[tuple(int(a.text) for a in e.args)])  # type: ignore[union-attr]
    if isinstance(e, ex.UnaryOp):
        return -evaluate(e.operand, env)
    assert isinstance(e, ex.BinOp)
    a, b = evaluate(e.left, env), evaluate(e.right, env)
    return {"+": lambda: a + b, "-": lambda: a - b, "*": lambda: a * b,
            "/": lambda: a / b}[e.op]()


def numpy_value(e: ex.Expr, values: dict[str, np.ndarray]) -> np.ndarray:
    """The same expression with NumPy's matrix algebra (vectors are columns)."""
    if isinstance(e, ex.Num):
        return np.array(float(e.text))
    if isinstance(e, ex.Name):
        v = values[e.text]
        return v.reshape(-1, 1) if v.ndim == 1 else v
    if isinstance(e, ex.Call):
        return numpy_value(e.args[0], values).T
    if isinstance(e, ex.UnaryOp):
        return -numpy_value(e.operand, values)
    assert isinstance(e, ex.BinOp)
    a, b = numpy_value(e.left, values), numpy_value(e.right, values)
    if e.op == "*":
        return a * b if a.ndim == 0 or b.ndim == 0 else a @ b
    return {"+": a + b, "-": a - b, "/": a / b}[e.op]


EXPRESSIONS = [
    "M * x + z", "transpose(M) * z - y", "N * x + 2 * y", "transpose(x) * y",
    "M * N * x", "-(K * z) + x / 4", "transpose(K) * N * y", "M * K", "transpose(M * K)",
]


def _expr(text: str) -> ex.Expr:
    from cyphy.semantics.dynamics.equations import parse_call

    return parse_call(f"f({text})").args[0]


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from(EXPRESSIONS))
def test_components_agree_with_numpy(seed: int, which: str) -> None:
    rng = np.random.default_rng(seed)
    values = {n: rng.normal(size=s) for n, s in SHAPES.items()}
    env: dict[str, object] = {}
    for name, v in values.items():
        if name in SPLIT:
            for k, item in enumerate(v.reshape(-1)):
                env[f"{name}_{k + 1}"] = item
        else:
            env[name] = v
    sc = Scalariser(SHAPES, SPLIT)
    e = _expr(which)
    expected = numpy_value(e, values)
    shape = sc.shape(e)
    flat = expected.reshape(-1)
    assert len(flat) == max(1, int(np.prod(shape)))
    for k, want in enumerate(flat):
        got = evaluate(sc.component(e, (k,) if shape else ()), env)
        assert got == pytest.approx(want, rel=1e-9, abs=1e-9), (which, k)


def test_notation_indices_count_from_one_and_become_components() -> None:
    one, two, seven = ex.Num("1"), ex.Num("2"), ex.Num("7")
    assert SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("F"), (two,)))) == [
        ex.BinOp("==", N("y"), N("F_2"))]
    assert SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("A"), (one,)))) == [
        ex.BinOp("==", N("y"), ex.Index(N("A"), (ex.Num("0"),)))]
    assert SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("R"), (two, one)))) == [
        ex.BinOp("==", N("y"), N("R_4"))]
    with pytest.raises(ScalariseError, match="index 7 out of a 6-vector"):
        SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("A"), (seven,))))
    with pytest.raises(ScalariseError, match="not a literal"):
        SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("A"), (N("i"),))))
    with pytest.raises(ScalariseError, match="not a vector or matrix of the model"):
        SC.predicate(ex.BinOp("==", N("y"), ex.Index(N("q"), (one,))))


# ---------------------------------------------------------------- library functions written out

LIB_SHAPES = {"w": (3,), "u": (3,), "V": (6,), "T": (4, 4), "c": (3,)}
LIB_SPLIT = frozenset({"w", "u", "V", "T"})  # c stays an indexed constant


def _lib_expected(name: str, values: dict[str, np.ndarray]) -> np.ndarray:
    """Each function from its definition (Modern Robotics), through NumPy and SciPy."""
    from scipy.spatial.transform import Rotation

    def skew(v: np.ndarray) -> np.ndarray:
        return np.array([np.cross(v, e) for e in np.eye(3)]).T  # column j is v x e_j

    w, u, V, T = values["w"], values["u"], values["V"], values["T"]
    theta = float(values["theta"])
    return {
        "skew(w)": lambda: skew(w),
        "ad(V)": lambda: np.block([[skew(V[:3]), np.zeros((3, 3))], [skew(V[3:]), skew(V[:3])]]),
        "ScrewAxis(w, c)": lambda: np.concatenate([w, values["c"]]),
        "cross(w, u)": lambda: np.cross(w, u),
        "dot(w, u)": lambda: np.dot(w, u),
        "norm(V)": lambda: np.linalg.norm(V),
        "Rot(c, theta)": lambda: Rotation.from_rotvec(
            theta * values["c"] / np.linalg.norm(values["c"])).as_matrix(),
        "Adjoint(T)": lambda: np.block([[T[:3, :3], np.zeros((3, 3))],
                                        [skew(T[:3, 3]) @ T[:3, :3], T[:3, :3]]]),
        "ad(V) * ScrewAxis(c, w) * theta": lambda: np.block(
            [[skew(V[:3]), np.zeros((3, 3))], [skew(V[3:]), skew(V[:3])]])
        @ np.concatenate([values["c"], w]) * theta,
        "identity(3) * w + zeroes(3, 3) * u": lambda: w,
    }[name]()


def _evaluate_call(e: ex.Expr, env: dict[str, object]) -> float:
    if isinstance(e, ex.Call):
        fn = {"sin": np.sin, "cos": np.cos, "sqrt": np.sqrt}[e.func.text]  # type: ignore
        return float(fn(_evaluate_call(e.args[0], env)))
    if isinstance(e, (ex.BinOp, ex.UnaryOp)):
        kids = {id(k): ex.Num(repr(_evaluate_call(k, env))) for k in e.children()}
        return evaluate(ex.transform(e, lambda n: kids.get(id(n))), env)
    return evaluate(e, env)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), which=st.sampled_from([
    "skew(w)", "ad(V)", "ScrewAxis(w, c)", "cross(w, u)", "dot(w, u)", "norm(V)",
    "Rot(c, theta)", "Adjoint(T)", "ad(V) * ScrewAxis(c, w) * theta",
    "identity(3) * w + zeroes(3, 3) * u"]))
def test_library_functions_written_out_agree_with_their_definitions(seed: int,
                                                                    which: str) -> None:
    rng = np.random.default_rng(seed)
    values = {n: rng.normal(size=s) for n, s in LIB_SHAPES.items()}
    values["theta"] = rng.normal()
    values["c"] /= np.linalg.norm(values["c"])  # Rot's axis is a unit vector
    env: dict[str, object] = {"theta": values["theta"], "c": values["c"]}
    for name in LIB_SPLIT:
        for k, item in enumerate(values[name].reshape(-1)):
            env[f"{name}_{k + 1}"] = item
    sc = Scalariser(LIB_SHAPES, LIB_SPLIT)
    e = _expr(which)
    flat = np.asarray(_lib_expected(which, values)).reshape(-1)
    shape = sc.shape(e)
    assert len(flat) == max(1, int(np.prod(shape)))
    for k, want in enumerate(flat):
        got = _evaluate_call(sc.component(e, (k,) if shape else ()), env)
        assert got == pytest.approx(want, rel=1e-9, abs=1e-9), (which, k)


def test_library_function_with_the_wrong_shape_is_refused() -> None:
    with pytest.raises(ScalariseError, match="ad takes a 6-vector here, not a 3-vector"):
        SC.predicate(ex.BinOp("==", N("F"), ex.BinOp("*", _expr("ad(v3)"), N("A"))))
    with pytest.raises(ScalariseError, match="inverse applied to a vector or matrix"):
        SC.predicate(ex.BinOp("==", N("R"), _expr("inverse(R)")))
