"""Symbol tables and types in the checker: every rule, valid and invalid, with the section
(§) of ../shared/docs/melfa-basic-iv.md it comes from."""

from __future__ import annotations

import pytest

from melfa.lang import Severity, check
from melfa.lang.model import FUNCTIONS


def found(text: str, points: tuple[str, ...] = ("P1", "P2", "P3")) -> list[tuple[int, str]]:
    return [(d.line, d.rule) for d in check(text, points)]


def only(text: str, rule: str) -> str:
    """The message of the one finding of `rule` (and no other finding)."""
    [d] = check(text, ("P1", "P2", "P3"))
    assert d.rule == rule, d
    return d.message


# --- §5 built-in functions: arities and argument kinds ---------------------------------------


@pytest.mark.parametrize(
    ("call", "usage"),
    [
        ("SIN(1, 2)", "SIN(number)"),
        ("DIST(P1)", "DIST(position, position)"),
        ("ATN2(1)", "ATN2(number, number)"),
        ('MID$("ABC")', "MID$(string, number[, number])"),
    ],
)
def test_wrong_argument_counts_are_errors_with_the_way_to_call(call: str, usage: str) -> None:
    """§5: arities from melfa.lang.model.FUNCTIONS (the simulator reads the same table)."""
    target = {"M": "M1", "C": "C1$"}["C" if "$" in call else "M"]
    [d] = check(f"{target} = {call}\n", ("P1",))
    assert (d.rule, d.code, d.severity) == ("wrong-argument-count", "L4220", Severity.ERROR)
    assert d.suggestion == f"Write it as {usage}."


@pytest.mark.parametrize(
    "call",
    ["SIN(1)", "ATN2(1, 2)", 'MID$("ABC", 2)', 'MID$("ABC", 2, 1)', "MAX(1, 2, 3)", "DIST(P1, P2)",
     "SETPOS(1, 2, 3)", 'LEN("A")', "RND(1)"],
)  # fmt: skip
def test_right_argument_counts_pass(call: str) -> None:
    """§5."""
    target = "C1$" if "$" in call else "P9" if call.startswith("SET") else "M1"
    assert found(f"{target} = {call}\n") == []


def test_every_function_of_the_language_has_an_arity() -> None:
    """§5: the list of the reference, each with 0 ≤ min ≤ max."""
    assert {"ABS", "ATN2", "CKSUM", "HEX$", "POSMID", "RDFL1", "SETJNT"} <= set(FUNCTIONS)
    assert all(0 <= f.min_args <= f.max_args for f in FUNCTIONS.values())


def test_an_argument_of_the_wrong_kind_is_a_type_mismatch() -> None:
    """§5: SIN takes a number, LEN a string, DIST positions."""
    assert found('C1$ = "A"\nM1 = SIN(C1$)\nM2 = LEN(5)\nM3 = DIST(P1, 5)\n') == [
        (2, "type-mismatch"),
        (3, "type-mismatch"),
        (4, "type-mismatch"),
    ]
    assert check('M1 = SIN("A")\n')[0].suggestion == "Convert it with VAL(), e.g. SIN(VAL(…))."


# --- §2.4 strings in arithmetic ----------------------------------------------------------


@pytest.mark.parametrize("expr", ["C1$ * 2", '"5" + 1', "2 - C1$", "C1$ = 5", '"A" * "B"'])
def test_strings_in_arithmetic_are_type_mismatches(expr: str) -> None:
    """§2.4 / §3: a string is not a number."""
    assert found(f'C1$ = "7"\nM1 = {expr}\n') == [(2, "type-mismatch")]


@pytest.mark.parametrize("expr", ['C1$ + "X"', 'C1$ = "X"', "VAL(C1$) * 2", "LEN(C1$) + 1"])
def test_strings_joined_compared_or_converted_pass(expr: str) -> None:
    """§2.4: + joins strings; comparisons of two strings are fine."""
    target = "C2$" if expr.endswith('+ "X"') else "M1"
    assert found(f'C1$ = "7"\n{target} = {expr}\n') == []


# --- §3 arrays ------------------------------------------------------------------------


def test_array_rules() -> None:
    """§3: DIM before use, once, with as many indices as sizes."""
    assert found("A(1) = 3\n") == [(1, "array-without-dim")]
    assert found("M1 = B(1)\nDIM B(3)\n") == [(1, "array-before-dim")]
    assert found("DIM B(3)\nDIM B(4)\n") == [(2, "duplicate-definition")]
    assert found("DIM B(3)\nM1 = B(1, 2)\n") == [(2, "array-dimensions")]
    assert found("DIM B(3), MC(2, 2)\nB(1) = 2\nM1 = B(1) + MC(1, 2)\n") == []


def test_a_call_to_a_misspelt_function_suggests_the_function() -> None:
    """§5: SQRT is not a function; as written it is an array that was never DIMmed."""
    [d] = check("M1 = SQRT(2)\n")
    assert d.rule == "array-without-dim"
    assert d.suggestion is not None and "SQR" in d.suggestion


def test_external_arrays_dimmed_elsewhere_are_not_reported() -> None:
    """§2.1: a name with _ as 2nd character is external (another program may DIM it)."""
    assert found("M_AB(2) = 1\n") == []


# --- §4.6 DEF FN, duplicate DEF ---------------------------------------------------------


def test_user_function_rules() -> None:
    """§4.6: DEF FN defines it, before the call, with its number of arguments."""
    assert found("M1 = FNSQ(2)\n") == [(1, "undefined-function")]
    assert found("M1 = FNSQ(2)\nDEF FNSQ(X) = X * X\n") == [(1, "function-before-def")]
    assert found("DEF FNSQ(X) = X * X\nM1 = FNSQ(2, 3)\n") == [(2, "wrong-argument-count")]
    assert found("DEF FNSQ(X) = X * X\nDEF FNSQ(Y) = Y\n") == [(2, "duplicate-definition")]
    assert found("DEF FNSQ(MX) = MX * MX\nM1 = FNSQ(2)\n") == []


def test_declaring_a_name_twice_is_an_error() -> None:
    """§2.1: L4350, redefinition with DIM/DEF."""
    [d] = check("DEF INTE KX\nDEF INTE KX\n")
    assert (d.rule, d.code, d.line) == ("duplicate-definition", "L4350", 2)
    assert "line 1" in d.message
    assert found("DEF INTE KX, KY\nDEF FLOAT KZ\n") == []


# --- §6 system variables ----------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "meant"),
    [("WAIT M_INN(8) = 1\n", "M_IN"), ("M_OUTT(17) = 1\n", "M_OUT"), ("M1 = M_SVOO\n", "M_SVO")],
)
def test_a_misspelt_system_variable_warns_with_the_right_name(text: str, meant: str) -> None:
    """§6: M_INN is not a system variable; as written it is an external variable."""
    [d] = check(text)
    assert (d.rule, d.severity) == ("unknown-system-variable", Severity.WARNING)
    assert d.suggestion is not None and d.suggestion.startswith(f"Write {meant} instead")


@pytest.mark.parametrize("name", ["M_COUNT", "M_01", "P_01", "M_ABC", "C_NAME$"])
def test_external_variables_of_ones_own_are_not_typos(name: str) -> None:
    """§2.1: `_` as 2nd character makes a global variable, a legal name."""
    value = {"P": "P1", "C": '"A"'}.get(name[0], "1")
    assert found(f"{name} = {value}\nM1 = 0\n") == []


def test_system_variable_index_and_assignability() -> None:
    """§6: M_IN takes an input number; M_IN and P_CURR are read-only, M_OUT is not."""
    assert found("M1 = M_IN\n") == [(1, "system-variable-index")]
    assert found("M_IN(3) = 1\n") == [(1, "read-only-system-variable")]
    assert found("P_CURR = P1\n") == [(1, "read-only-system-variable")]
    assert found("M_OUT(17) = 1\nM_TIMER(1) = 0\nP_TOOL = P1\nM1 = M_IN(8) + M_SVO\n") == []


# --- §2.2 constants, §4.5 interrupts, §4.1 PLT ------------------------------------------


def test_position_constants_have_at_most_eight_elements_and_two_flags() -> None:
    """§2.2: (X,Y,Z,A,B,C[,L1,L2])(FL1,FL2)."""
    assert found("P9 = (1,2,3,4,5,6,7,8,9)(7,0)\n") == [(1, "position-elements")]
    assert found("P9 = (1,2,3,4,5,6)(7,0,1)\n") == [(1, "position-elements")]
    assert found("P9 = (1,2,3,4,5,6,7,8)(7,0)\nJ9 = (1,2,3,4,5,6)\n") == []


def test_def_act_priorities_and_act_numbers() -> None:
    """§4.6: DEF ACT priorities 1…8; ACT 0 is the master switch."""
    program = "DEF ACT {}, M_IN(1) = 1 GOSUB *IRQ\nACT {} = 1\nEND\n*IRQ\nRETURN 1\n"
    assert found(program.format(9, 1)) == [(1, "value-out-of-range")]
    assert found(program.format(1, 9)) == [(2, "value-out-of-range")]
    assert found(program.format(1, 0)) == []


def test_an_interrupt_routine_ends_with_return_0_or_1() -> None:
    """§4.5: a plain RETURN ends a GOSUB routine, RETURN 0|1 an interrupt routine."""
    irq = "DEF ACT 1, M_IN(1) = 1 GOSUB *IRQ\nACT 1 = 1\nEND\n*IRQ\nM1 = 0\nRETURN{}\n"
    assert found(irq.format("")) == [(6, "interrupt-return")]
    assert found(irq.format(" 1")) == []
    sub = "GOSUB *SUB\nEND\n*SUB\nRETURN{}\n"
    assert found(sub.format(" 0")) == [(4, "interrupt-return")]
    assert found(sub.format("")) == []


def test_plt_as_a_value_is_iv() -> None:
    """§4.1: COSIMIR's own palette example `210 PLACE=PLT 1,M1`."""
    assert found("DEF PLT 1, P1, P2, P3, , 4, 3, 1\nM1 = 2\nPLACE = PLT 1, M1\nMOV PLACE\n") == []
    assert found("P10 = PLT 9, 1\n") == [(1, "value-out-of-range")]
    [d] = check("MOV PLT 1, 5\n")
    assert d.suggestion == "Write it in parentheses, e.g. MOV (PLT 1, 5)."
