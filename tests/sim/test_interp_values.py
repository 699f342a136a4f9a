"""Values, operators, type rules and built-in functions of the interpreter."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.kin import Pose, pose_inv, pose_mul
from melfa.lang import ast
from melfa.lang.parser import parse
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp import errors, posmath
from melfa.sim.interp.armport import ArmPort, from_pose, to_pose
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.values import Joints, Position, Value


def interp() -> Interpreter:
    return Interpreter(ArmPort(SimulatedArm(servo_on=True)))


def ev(expr: str, it: Interpreter | None = None) -> Value:
    """Evaluate one expression as the interpreter compiles it."""
    it = it or interp()
    line = parse(f"ZZ = {expr}").lines[0]
    assert isinstance(line.statement, ast.Assign), line
    return it.compiler.exprs.value(line.statement.value)()


def run_error(expr: str) -> errors.RunError:
    with pytest.raises(errors.RunError) as info:
        ev(expr)
    return info.value


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("3 * 4", 12),
        ("7 / 2", 3.5),
        ("7 \\ 2", 3),
        ("-7 \\ 2", -3),
        ("7 MOD 3", 1),
        ("-7 MOD 3", -1),
        ("7.6 MOD 3", 2),  # reals are rounded first for MOD
        ("2 ^ 10", 1024),
        ("2 + 3 * 4", 14),
        ("(2 + 3) * 4", 20),
        ("-2 ^ 2", -4),  # ^ binds tighter than unary minus
        ("1 << 4", 16),
        ("256 >> 2", 64),
        ("15 AND 256", 0),
        ("12 OR 3", 15),
        ("6 XOR 3", 5),
        ("NOT 0", -1),
        ("3 > 2", 1),
        ("3 < 2", 0),
        ("3 >= 3", 1),
        ("2 <> 2", 0),
        ("2 >< 3", 1),
        ('"AB" + "CD"', "ABCD"),
        ('"AB" = "AB"', 1),
        ("&HFF", 255),
        ("&B101", 5),
    ],
)
def test_operators(expr: str, expected: Value) -> None:
    result = ev(expr)
    assert result == expected
    assert type(result) is type(expected)


def test_integer_division_gives_a_real_even_when_exact() -> None:
    result = ev("6 / 3")
    assert result == 2.0
    assert isinstance(result, float)


@pytest.mark.parametrize("expr", ["1 / 0", "1 \\ 0", "5 MOD 0", "P_CURR / 0"])
def test_division_by_zero_is_an_error(expr: str) -> None:
    assert run_error(expr).number == errors.DIVISION_BY_ZERO


@pytest.mark.parametrize(
    ("expr", "expected"),
    [
        ("ABS(-3)", 3),
        ("CINT(2.5)", 3),
        ("CINT(-2.5)", -3),
        ("FIX(-2.7)", -2),
        ("INT(-2.7)", -3),
        ("SGN(-5)", -1),
        ("SQR(16)", 4.0),
        ("LN(EXP(2))", 2.0),
        ("LOG(1000)", 3.0),
        ("MAX(1, 5, 3)", 5),
        ("MIN(4, -1, 3)", -1),
        ("RAD(180)", math.pi),
        ("DEG(RAD(45))", 45.0),
        ("SIN(RAD(90))", 1.0),
        ("COS(0)", 1.0),
        ("ATN(1)", math.pi / 4),
        ("ATN2(1, 1)", math.pi / 4),
        ('LEN("ABC")', 3),
        ('ASC("A")', 65),
        ('VAL("12.5")', 12.5),
        ('VAL("&H10")', 16),
        ('STRPOS("HELLO", "LL")', 3),
        ("CHR$(65)", "A"),
        ('LEFT$("HELLO", 2)', "HE"),
        ('MID$("HELLO", 2, 3)', "ELL"),
        ('RIGHT$("HELLO", 3)', "LLO"),
        ("STR$(10)", "10"),
        ("STR$(2.5)", "2.5"),
        ("HEX$(255)", "FF"),
        ("HEX$(-1)", "FFFF"),
        ("HEX$(10, 4)", "000A"),
        ("BIN$(5)", "101"),
    ],
)
def test_functions(expr: str, expected: Value) -> None:
    result = ev(expr)
    if isinstance(expected, float):
        assert result == pytest.approx(expected)
    else:
        assert result == expected


@pytest.mark.parametrize("expr", ["SQR(-1)", "LN(0)", 'ASC("")', "CHR$(300)"])
def test_function_argument_errors(expr: str) -> None:
    assert run_error(expr).number == errors.ARGUMENT_OUT_OF_RANGE


def test_rnd_is_in_unit_interval_and_reseedable() -> None:
    it = interp()
    a = ev("RND(7)", it)
    b = ev("RND(7)", it)
    assert isinstance(a, float)
    assert 0.0 <= a < 1.0
    assert a == b  # the same non-zero seed restarts the sequence


def test_unsupported_function_is_refused_clearly() -> None:
    err = run_error('CVI("AB")')
    assert err.number == errors.NOT_SUPPORTED
    assert "not supported" in err.message


def test_mixing_types_is_a_type_combination_error() -> None:
    assert run_error('1 + "A"').number == errors.TYPE_COMBINATION
    assert run_error("2 * P_CURR").number == errors.TYPE_COMBINATION  # M * P [S2 p.163]


# --- positions --------------------------------------------------------------------------


def test_position_constants_are_degrees_and_elements_radians() -> None:
    it = interp()
    it.state.vars["P1"] = ev("(100, 200, 300, 90, -45, 180)(7, 0)", it)
    assert ev("P1.X", it) == 100.0
    assert ev("P1.A", it) == pytest.approx(math.pi / 2)
    assert ev("P1.B", it) == pytest.approx(-math.pi / 4)
    assert ev("P1.FL1", it) == 7
    assert ev("DEG(P1.C)", it) == pytest.approx(180.0)


def test_joint_constants_take_their_type_from_the_variable() -> None:
    it = interp()
    it.load("10 J1 = (10, 20, 30, 40, 50, 60)\n20 M1 = J1.J3\n30 END\n")
    it.start(0.0)
    it.advance(1.0)
    assert isinstance(it.state.vars["J1"], Joints)
    assert it.state.vars["M1"] == pytest.approx(math.radians(30))


def test_position_addition_is_element_wise_in_world() -> None:
    it = interp()
    it.state.vars["P1"] = Position.from_degrees([100, 0, 300, 180, 0, 90])
    it.state.vars["P2"] = Position.from_degrees([10, 20, 30, 0, 0, 10])
    p = ev("P1 + P2", it)
    assert isinstance(p, Position)
    assert (p.x, p.y, p.z) == (110.0, 20.0, 330.0)
    assert math.degrees(p.c) == pytest.approx(100.0)
    q = ev("P1 - P2", it)
    assert isinstance(q, Position)
    assert (q.x, q.y, q.z) == (90.0, -20.0, 270.0)


def test_position_multiplication_is_in_the_tool_frame() -> None:
    it = interp()
    it.state.vars["P1"] = Position.from_degrees([400, 0, 645, 180, 0, 180])
    p = ev("P1 * (0, 0, -50, 0, 0, 0)", it)  # hand down: tool -Z is world +Z
    assert isinstance(p, Position)
    assert (p.x, p.y, p.z) == pytest.approx((400.0, 0.0, 695.0))
    back = ev("(P1 * (10, 20, 30, 0, 0, 45)) / (10, 20, 30, 0, 0, 45)", it)
    assert isinstance(back, Position)
    assert back.to_degrees() == pytest.approx(it.state.vars["P1"].to_degrees(), abs=1e-9)


def test_position_times_number_scales() -> None:
    it = interp()
    it.state.vars["P1"] = Position.from_degrees([10, 20, 30, 0, 0, 0])
    p = ev("P1 * 2", it)
    assert isinstance(p, Position)
    assert (p.x, p.y, p.z) == (20.0, 40.0, 60.0)


def test_inv_and_dist() -> None:
    it = interp()
    it.state.vars["P1"] = Position.from_degrees([100, 50, 300, 30, 20, 10])
    ident = ev("P1 * INV(P1)", it)
    assert isinstance(ident, Position)
    assert ident.to_degrees() == pytest.approx((0, 0, 0, 0, 0, 0), abs=1e-9)
    it.state.vars["P2"] = Position.from_degrees([103, 54, 300, 0, 0, 0])
    assert ev("DIST(P1, P2)", it) == pytest.approx(5.0)


def test_flag_functions() -> None:
    it = interp()
    it.state.vars["P1"] = Position.from_degrees([0, 0, 0, 0, 0, 0], 7, 0x00100000)
    assert ev("RDFL1(P1, 0)", it) == "R"
    assert ev('RDFL1(SETFL1(P1, "LBF"), 1)', it) == "B"
    assert ev("RDFL2(P1, 6)", it) == 1
    p = ev("SETFL2(P1, 6, -1)", it)
    assert isinstance(p, Position)
    assert p.fl2 == 0x00F00000


finite = st.floats(min_value=-500, max_value=500, allow_nan=False)
angle = st.floats(min_value=-179, max_value=179, allow_nan=False)
poses = st.builds(Pose, finite, finite, finite, angle, st.floats(-80, 80), angle)


@settings(max_examples=50, deadline=None)
@given(poses, poses)
def test_position_arithmetic_agrees_with_kin(p1: Pose, p2: Pose) -> None:
    """One convention for the whole project: the interpreter's P1*P2 is kin's pose_mul."""
    ours = posmath.multiply(from_pose(p1), from_pose(p2))
    theirs = pose_mul(p1, p2)
    t1 = to_pose(ours)
    assert (t1.x, t1.y, t1.z) == pytest.approx((theirs.x, theirs.y, theirs.z), abs=1e-6)
    r_ours = posmath.rotation(ours.a, ours.b, ours.c)
    r_theirs = posmath.rotation(*(math.radians(v) for v in theirs.abc))
    for row_o, row_t in zip(r_ours, r_theirs, strict=True):
        assert row_o == pytest.approx(row_t, abs=1e-9)
    inv = to_pose(posmath.inverse(from_pose(p1)))
    kinv = pose_inv(p1)
    assert (inv.x, inv.y, inv.z) == pytest.approx((kinv.x, kinv.y, kinv.z), abs=1e-6)
