"""Statements without motion: variables, declarations, flow control, I/O, errors."""

from __future__ import annotations

import pytest

from melfa.sim.arm import SimulatedArm
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.fast import Run, run_fast, simulate
from melfa.sim.interp.interpreter import STEP_TIME_S, Interpreter
from melfa.sim.interp.io import IOState
from melfa.sim.interp.values import Value
from melfa.sim.runner import RunnerStatus
from melfa.sim.syntax import first_syntax_error


def program(*lines: str) -> str:
    """Number the lines 10, 20, …"""
    return "".join(f"{10 * (i + 1)} {text}\n" for i, text in enumerate(lines))


def run(*lines: str, io: IOState | None = None) -> Run:
    return simulate(program(*lines), io=io, max_time=60)


def variables(*lines: str) -> dict[str, Value]:
    r = run(*lines)
    assert r.interp.error is None, r.interp.error
    assert r.interp.status is RunnerStatus.FINISHED
    return r.interp.state.vars


def fails(*lines: str) -> tuple[int, int | None]:
    r = run(*lines)
    assert r.interp.status is RunnerStatus.FAILED
    err = r.interp.error
    assert err is not None
    return err.number, err.line


# --- variables and declarations -------------------------------------------------------------


def test_assignment_and_arithmetic() -> None:
    v = variables("M1 = 3", "M2 = M1 * 4 + 1", 'C1$ = "N=" + STR$(M2)', "END")
    assert v["M2"] == 13
    assert v["C1$"] == "N=13"


def test_def_inte_rounds_and_checks_range() -> None:
    assert variables("DEF INTE KX", "KX = 2.6", "END")["KX"] == 3
    number, line = fails("DEF INTE KX", "KX = 32767", "KX = KX + 1", "END")
    assert (number, line) == (errors.NUMERIC_OVERFLOW, 30)


def test_def_float_double_char_pos_jnt() -> None:
    v = variables(
        "DEF FLOAT FA",
        "DEF DOUBLE DB",
        "DEF CHAR NAME",
        "DEF POS WORK",
        "DEF JNT SAFE",
        "FA = 1",
        'NAME = "ROBOT"',
        "WORK = (1, 2, 3, 0, 0, 0)(7, 0)",
        "SAFE = (0, 0, 90, 0, 90, 0)",
        "END",
    )
    assert v["FA"] == 1.0
    assert isinstance(v["FA"], float)
    assert v["DB"] == 0.0
    assert v["NAME"] == "ROBOT"
    assert type(v["WORK"]).__name__ == "Position"
    assert type(v["SAFE"]).__name__ == "Joints"


def test_storing_the_wrong_type_is_an_error() -> None:
    assert fails('M1 = "TEXT"', "END") == (errors.TYPE_COMBINATION, 10)
    assert fails("DEF CHAR NAME", "NAME = 5", "END") == (errors.TYPE_COMBINATION, 20)


def test_reading_an_unassigned_variable_is_l3700() -> None:
    assert fails("M1 = 1", "M2 = M1 + M9", "END") == (errors.UNDEFINED_VARIABLE, 20)


def test_arrays() -> None:
    v = variables(
        "DIM MA(3), MB(2, 2)",
        "FOR I = 1 TO 3",
        "MA(I) = I * I",
        "NEXT I",
        "MB(2, 1) = MA(3)",
        "M1 = MB(2, 1)",
        "END",
    )
    assert v["M1"] == 9


def test_array_bounds_and_undefined_elements() -> None:
    assert fails("DIM MA(3)", "MA(4) = 1", "END") == (errors.ARRAY_ELEMENT, 20)
    assert fails("DIM MA(3)", "M1 = MA(2)", "END") == (errors.UNDEFINED_VARIABLE, 20)
    assert fails("MA(1) = 1", "END") == (errors.VARIABLE_NOT_DEFINED, 10)


def test_element_assignment() -> None:
    v = variables(
        "P1 = (100, 0, 300, 180, 0, 180)(7, 0)",
        "P1.X = P1.X + 10",
        "P1.C = P1.C - RAD(90)",
        "J1 = (0, 0, 90, 0, 90, 0)",
        "J1.J1 = RAD(15)",
        "END",
    )
    p = v["P1"]
    j = v["J1"]
    assert p.x == 110.0  # type: ignore[union-attr]
    assert p.to_degrees()[5] == pytest.approx(90.0)  # type: ignore[union-attr]
    assert j.to_degrees()[0] == pytest.approx(15.0)  # type: ignore[union-attr]


def test_def_fn() -> None:
    v = variables("DEF FNSQ(MX) = MX * MX", "MX = 5", "M1 = FNSQ(3) + MX", "END")
    assert v["M1"] == 14  # the parameter does not leak into MX


# --- flow ---------------------------------------------------------------------------------


def test_goto_and_labels() -> None:
    v = variables("M1 = 0", "GOTO *SKIP", "M1 = 99", "*SKIP", "M2 = 1", "GOTO 80", "M2 = 5", "END")
    assert v["M1"] == 0
    assert v["M2"] == 1


def test_gosub_return_nested() -> None:
    v = variables(
        "M1 = 0",
        "GOSUB *A",
        "M1 = M1 * 10",
        "END",
        "*A",
        "M1 = M1 + 1",
        "GOSUB *B",
        "RETURN",
        "*B",
        "M1 = M1 + 2",
        "RETURN",
    )
    assert v["M1"] == 30


def test_return_without_gosub_is_l3840() -> None:
    assert fails("M1 = 1", "RETURN", "END") == (errors.RETURN_WITHOUT_GOSUB, 20)


def test_jump_to_a_missing_line_or_label() -> None:
    assert fails("GOTO 999", "END") == (errors.LINE_NOT_FOUND, 10)
    assert fails("M1 = 1", "GOSUB *NOWHERE", "END") == (errors.JUMP_DESTINATION_MISSING, 20)


def test_on_goto_and_on_gosub() -> None:
    v = variables(
        "M1 = 2",
        "ON M1 GOTO 40, 60",
        "M2 = -1",
        "M2 = 1",
        "GOTO 70",
        "M2 = 2",
        "ON 3 GOSUB *X",  # out of the list: falls through
        "ON 1 GOSUB *X",
        "END",
        "*X",
        "M3 = 7",
        "RETURN",
    )
    assert v["M2"] == 2
    assert v["M3"] == 7


@pytest.mark.parametrize(
    ("m1", "expected"),
    [(5, 1), (20, 2)],
)
def test_single_line_if_forms(m1: int, expected: int) -> None:
    v = variables(
        f"M1 = {m1}",
        "IF M1 > 10 THEN *BIG ELSE 40",
        "END",
        "M2 = 1",
        "IF M1 < 10 THEN END",
        "*BIG",
        "IF M1 > 10 THEN M2 = 2 ELSE M2 = -1",
        "END",
    )
    assert v["M2"] == expected


def test_block_if_else_endif_nested() -> None:
    v = variables(
        "M1 = 3",
        "IF M1 > 2 THEN",
        "  IF M1 > 5 THEN",
        "    M2 = 1",
        "  ELSE",
        "    M2 = 2",
        "  ENDIF",
        "  M3 = 1",
        "ELSE",
        "  M2 = 3",
        "ENDIF",
        "END",
    )
    assert (v["M2"], v["M3"]) == (2, 1)


def test_for_next_step_zero_trip_and_multiple_counters() -> None:
    v = variables(
        "M1 = 0",
        "FOR I = 10 TO 1 STEP -3",
        "M1 = M1 + I",
        "NEXT",
        "M2 = 0",
        "FOR I = 5 TO 1",  # zero-trip: the body never runs
        "M2 = 99",
        "NEXT I",
        "M3 = 0",
        "FOR A = 1 TO 3",
        "FOR B = 1 TO 4",
        "M3 = M3 + 1",
        "NEXT B, A",
        "END",
    )
    assert v["M1"] == 10 + 7 + 4 + 1
    assert v["M2"] == 0
    assert v["M3"] == 12


def test_zero_trip_inner_loop_of_a_double_next() -> None:
    v = variables(
        "M3 = 0",
        "FOR A = 1 TO 3",
        "FOR B = A TO 2",
        "M3 = M3 + 1",
        "NEXT B, A",
        "END",
    )
    assert v["M3"] == 3  # A=1: B=1,2; A=2: B=2; A=3: zero-trip


def test_while_wend_and_break() -> None:
    v = variables(
        "M1 = 0",
        "WHILE M1 < 100",
        "M1 = M1 + 7",
        "IF M1 > 20 THEN BREAK",
        "WEND",
        "M2 = 0",
        "WHILE 0",
        "M2 = 1",
        "WEND",
        "END",
    )
    assert v["M1"] == 21
    assert v["M2"] == 0


@pytest.mark.parametrize(("m1", "expected"), [(1, 10), (3, 30), (7, 40), (-5, 50), (0, 99)])
def test_select_case(m1: int, expected: int) -> None:
    v = variables(
        f"M1 = {m1}",
        "SELECT M1",
        "CASE 1",
        "M2 = 10",
        "BREAK",
        "CASE 2 TO 4",
        "M2 = 30",
        "BREAK",
        "CASE IS >= 5",
        "M2 = 40",
        "BREAK",
        "CASE IS < 0",
        "M2 = 50",
        "BREAK",
        "DEFAULT",
        "M2 = 99",
        "BREAK",
        "END SELECT",
        "END",
    )
    assert v["M2"] == expected


def test_structure_errors_stop_at_their_line() -> None:
    assert fails("M1 = 1", "NEXT", "END") == (errors.FOR_NEXT_UNMATCH, 20)
    assert fails("M1 = 1", "WEND", "END") == (errors.WHILE_WEND_UNMATCH, 20)
    assert fails("FOR I = 1 TO 2", "END") == (errors.FOR_NEXT_UNMATCH, 10)


def refused_at_load(text: str) -> tuple[int, int | None]:
    with pytest.raises(errors.RunError) as caught:
        simulate(text)
    return caught.value.number, caught.value.line


def test_lines_the_checker_refuses_are_refused_at_load() -> None:
    # As the controller refuses them when the program is written to it: nothing runs.
    assert refused_at_load("10 M1 = 1\n20 MOV ,,,\n30 END\n") == (errors.SYNTAX_ERROR, 20)
    assert refused_at_load("10 SERVO ON (remark)\n20 END\n") == (errors.SYNTAX_ERROR, 10)
    assert refused_at_load("0 M1 = 1\n10 END\n") == (errors.LINE_NUMBER_RANGE, 0)
    long_step = "10 M1 = " + "1 + " * 40 + "1\n20 END\n"
    assert refused_at_load(long_step) == (errors.STATEMENT_TOO_LONG, 10)


def test_the_last_of_two_lines_with_one_step_number_is_kept() -> None:
    r = simulate("10 M1 = 1\n20 M1 = 2\n20 M1 = 3\n30 END\n")
    assert r.interp.state.vars["M1"] == 3
    assert [s.number for s in r.interp.state.steps] == [10, 20, 30]


def test_user_error() -> None:
    assert fails("M1 = 1", "ERROR 9100", "END") == (9100, 20)
    r = run("ERROR 9200", "M1 = 5", "END")  # caution level: recorded, the program goes on
    assert r.interp.status is RunnerStatus.FINISHED
    assert r.interp.state.caution is not None
    assert r.interp.state.caution.number == 9200
    assert fails("ERROR 5")[0] == errors.ARGUMENT_OUT_OF_RANGE


def test_end_stops_and_lines_run_in_step_number_order() -> None:
    r = simulate("30 M1 = M1 * 10\n10 M1 = 1\n20 M1 = M1 + 1\n40 END\n50 M1 = 0\n")
    assert r.interp.state.vars["M1"] == 20
    assert r.interp.line == 40


def test_refused_statements_say_so() -> None:
    number, line = fails('CALLP "SUB"', "END")
    assert (number, line) == (errors.NOT_SUPPORTED, 10)


# --- I/O, timers ------------------------------------------------------------------------------


def test_outputs_inputs_and_widths() -> None:
    io = IOState()
    io.set_inputs(8, 8, 0xA5)
    r = run("M_OUT(3) = 1", "M_OUT8(16) = &H0F", "M1 = M_IN8(8)", "M2 = M_IN(8)", "END", io=io)
    assert io.output(3) == 1
    assert io.read_outputs(16, 8) == 0x0F
    assert r.interp.state.vars["M1"] == 0xA5
    assert r.interp.state.vars["M2"] == 1


def test_pulse_output_resets_after_its_time() -> None:
    io = IOState()
    r = run("M_OUT(17) = 1 DLY 0.5", "M1 = M_OUT(17)", "DLY 1", "M2 = M_OUT(17)", "END", io=io)
    assert r.interp.state.vars["M1"] == 1
    assert r.interp.state.vars["M2"] == 0


def test_def_io_variables() -> None:
    io = IOState()
    io.set_input(4, 1)
    r = run("DEF IO LAMP = BIT, 6", "LAMP = 1", "DEF IO SENS = BIT, 4", "M1 = SENS", "END", io=io)
    assert io.output(6) == 1
    assert r.interp.state.vars["M1"] == 1


def test_timer_is_settable_and_counts_simulated_seconds() -> None:
    v = variables("M_TIMER(1) = 0", "DLY 2.5", "M1 = M_TIMER(1)", "END")
    assert v["M1"] == pytest.approx(2.5 + STEP_TIME_S)  # the setting step took its time


# --- valid IV the interpreter refused (issue 25) ----------------------------------------


def test_plain_relm_fractional_overrides_and_a_suffixed_declared_name_run() -> None:
    v = variables("GETM 1", "RELM", "OVRD 0.5", "JOVRD 0.01", "DEF INTE KPAT", "KPAT% = 3", "END")
    assert v["KPAT%"] == 3
    assert fails("OVRD 0", "END") == (errors.ARGUMENT_OUT_OF_RANGE, 10)


def test_a_busy_wait_loop_takes_a_step_time_per_step() -> None:
    # *L / M1 = M1 + 1 / IF M_IN(3)=0 THEN GOTO *L: one minute of program time is about
    # 2,800 passes (three steps each, the label's line too, at STEP_TIME_S), not the
    # millions a free clock ran (--max-time 60 took a quarter of an hour).
    text = "5 M1 = 0\n10 *L\n20 M1 = M1 + 1\n30 IF M_IN(3) = 0 THEN GOTO *L\n"
    r = simulate(text, max_time=60)
    assert r.interp.status is RunnerStatus.RUNNING
    assert r.interp.state.vars["M1"] == pytest.approx(60 / (3 * STEP_TIME_S), rel=0.01)


def test_input_reads_a_scripted_line_and_waits_for_one() -> None:
    it = Interpreter(ArmPort(SimulatedArm()))
    it.load('10 OPEN "COM1:" AS #1\n20 INPUT #1, M1, C1$, M2\n30 M3 = M1 + M2\n40 END\n')
    it.start(0.0)
    run_fast(it, max_time=1)
    assert (it.status, it.waiting, it.line) == (RunnerStatus.RUNNING, True, 20)
    it.feed_line(1, "12, hello, 3.5")
    run_fast(it, max_time=1)
    assert it.status is RunnerStatus.FINISHED
    assert {k: it.state.vars[k] for k in ("M1", "C1$", "M2", "M3")} == {
        "M1": 12,
        "C1$": "hello",
        "M2": 3.5,
        "M3": 15.5,
    }


def test_input_of_text_into_a_number_stops_with_l4390() -> None:
    it = Interpreter(ArmPort(SimulatedArm()))
    it.load("10 INPUT #2, M1\n20 END\n")
    it.feed_line(2, "ready")
    it.start(0.0)
    run_fast(it, max_time=1)
    assert it.error is not None and (it.error.number, it.error.line) == (
        errors.TYPE_COMBINATION,
        10,
    )


def test_the_virtual_controller_refuses_to_store_what_the_interpreter_refuses() -> None:
    # SAVE/EMDAT refuse these, so a stored program always loads.
    assert first_syntax_error("0 M1 = 1\n") == (errors.LINE_NUMBER_RANGE, 1)
    assert first_syntax_error("10 M1 = " + "1 + " * 40 + "1\n") == (errors.STATEMENT_TOO_LONG, 128)
    assert first_syntax_error("10 SERVO ON (remark)\n") == (errors.SYNTAX_ERROR, 13)
