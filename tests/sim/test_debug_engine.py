"""The debug engine on the real interpreter and simulated arm, driven by a test clock."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.sim.debug.engine import (
    INSTANT,
    REAL_TIME,
    DebugError,
    Debugger,
    RunState,
    Speed,
    StopReason,
)
from melfa.sim.debug.view import VarKind, melfa_text
from melfa.sim.interp.values import Joints, Position

POINTS = (
    "DEF POS P1=(400.00,100.00,500.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(300.00,-200.00,400.00,180.00,0.00,180.00)(7,0)\n"
)

SUBS = """SERVO ON
M1 = 1
*LOOP
GOSUB *SUB
M1 = M1 + 1
IF M1 < 3 THEN GOTO *LOOP
END
*SUB
M2 = M1 * 10
RETURN
"""


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def make(program: str, speed: Speed = INSTANT, points: str = POINTS) -> tuple[Debugger, Clock]:
    clock = Clock()
    return Debugger(program, points, clock=clock, speed=speed), clock


def line(d: Debugger) -> int:
    loc = d.location
    assert loc is not None
    return loc.line


def test_a_breakpoint_on_a_line_stops_before_that_statement() -> None:
    d, _ = make(SUBS)
    bp = d.break_line(5)
    d.run()
    stop = d.poll()
    assert stop is not None
    assert (stop.reason, stop.location.line, stop.breakpoint) == (StopReason.BREAKPOINT, 5, bp.id)
    assert stop.location.source == "M1 = M1 + 1"
    assert d.evaluate("M1") == "1"  # line 5 has not run yet
    d.continue_()
    assert d.poll() is not None and d.evaluate("M1") == "2"
    d.delete(bp.id)
    d.continue_()
    end = d.poll()
    assert end is not None and end.reason is StopReason.END
    assert d.state is RunState.FINISHED and d.evaluate("M1") == "3"


def test_a_breakpoint_on_a_label_and_on_a_blank_line() -> None:
    d, _ = make("SERVO ON\n\nM1 = 5\nEND\n")
    assert d.break_line(2).line == 3  # a blank line: the next statement
    d2, _ = make(SUBS)
    assert d2.break_label("*sub").line == 8
    with pytest.raises(DebugError, match=r"no label \*NOPE.*\*LOOP, \*SUB"):
        d2.break_label("NOPE")
    with pytest.raises(DebugError, match="outside the program"):
        d2.break_line(99)
    with pytest.raises(DebugError, match="no breakpoint 7"):
        d2.delete(7)


def test_step_goes_into_gosub_and_next_steps_over_it() -> None:
    d, _ = make(SUBS)
    d.break_line(4)
    d.run()
    d.poll()
    assert line(d) == 4
    d.step()
    d.poll()
    assert line(d) == 8 and [f.location.line for f in d.where()] == [8, 4]
    d.step()
    d.poll()
    assert line(d) == 9
    d.step_out()
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.STEP
    assert line(d) == 5 and len(d.where()) == 1
    d.step()
    d.poll()
    d.step()
    d.poll()  # IF … GOTO *LOOP
    assert line(d) == 3
    d.step()
    d.poll()
    assert line(d) == 4
    d.step_over()
    d.poll()
    assert line(d) == 5 and d.evaluate("M2") == "20"


def test_finish_outside_a_subroutine_is_refused() -> None:
    d, _ = make(SUBS)
    d.break_line(2)
    d.run()
    d.poll()
    with pytest.raises(DebugError, match="not inside a subroutine"):
        d.step_out()


def test_step_over_stops_at_a_breakpoint_inside_the_subroutine() -> None:
    d, _ = make(SUBS)
    d.break_line(4)
    d.run()
    d.poll()
    bp = d.break_line(9)
    d.step_over()
    stop = d.poll()
    assert stop is not None and (stop.reason, stop.breakpoint, line(d)) == (
        StopReason.BREAKPOINT,
        bp.id,
        9,
    )


def test_run_to_cursor() -> None:
    d, _ = make(SUBS)
    d.run_to(6)
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.STEP and line(d) == 6


def test_an_input_releases_a_wait() -> None:
    d, _ = make("SERVO ON\nWAIT M_IN(3) = 1\nM1 = 7\nEND\n")
    d.run()
    assert d.poll() is None
    assert d.state is RunState.RUNNING and d.waiting and line(d) == 2
    assert d.poll() is None  # nobody set it: still waiting
    d.set_input(3, 1)
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.END and d.evaluate("M1") == "7"
    assert any(v.name == "M_IN(3)" and v.kind is VarKind.INPUT for v in d.variables())


def test_a_run_time_error_stops_on_its_line_with_the_controllers_number() -> None:
    d, _ = make("SERVO ON\nM1 = 2\nM2 = M9 + 1\nEND\n")
    d.run()
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.ERROR
    assert stop.error is not None
    assert (stop.error.number, stop.error.code, stop.location.line) == (3700, "L3700", 3)
    assert stop.error.text == "L3700 Undefined (uninitialised) variable: variable M9 has no value"
    assert d.state is RunState.FAILED
    with pytest.raises(DebugError, match="not running"):
        d.continue_()


def test_pause_mid_motion_then_continue_redoes_the_move() -> None:
    d, clock = make("SERVO ON\nOVRD 10\nMOV P1\nMOV P2\nEND\n", speed=REAL_TIME)
    d.run()
    clock.t = 0.3
    assert d.poll() is None
    assert line(d) == 3 and d.arm.is_moving(d.interp.now)
    stop = d.pause()
    assert stop is not None and stop.reason is StopReason.PAUSE and stop.location.line == 3
    assert not d.arm.is_moving(d.interp.now)  # the arm decelerated to a stop
    paused_at = d.interp.now
    clock.t = 100.0  # time passes while paused: the program does not move
    assert d.poll() is None and d.interp.now == paused_at
    d.continue_()
    clock.t = 130.0
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.END
    assert d.evaluate("P_CURR") == melfa_text(
        Position.from_degrees((300, -200, 400, 180, 0, 180), 7, 0)
    )


def test_speed_times_n_runs_n_simulated_seconds_per_clock_second() -> None:
    d, clock = make("DLY 3\nM1 = 1\nEND\n", speed=Speed.times(4))
    d.run()
    clock.t = 0.5
    assert d.poll() is None and d.time == pytest.approx(2.0)
    clock.t = 1.0
    assert d.poll() is not None and d.evaluate("M1") == "1"


def test_hlt_stops_and_continue_goes_on_with_the_next_line() -> None:
    d, _ = make("M1 = 1\nHLT\nM1 = 2\nEND\n")
    d.run()
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.HLT and line(d) == 3
    d.step()
    d.poll()
    assert d.evaluate("M1") == "2" and line(d) == 4


def test_an_endless_loop_at_instant_speed_stops_at_the_time_limit() -> None:
    clock = Clock()
    d = Debugger("M1 = 0\n*L\nM1 = M1 + 1\nGOTO *L\n", clock=clock, speed=INSTANT, max_time=2.0)
    d.run()
    stop = None
    for _ in range(10):
        stop = d.poll() or stop
    assert stop is not None and stop.reason is StopReason.TIME_LIMIT
    assert d.state is RunState.PAUSED


def test_variables_mark_what_the_last_step_changed() -> None:
    d, _ = make('M1 = 1\nS$ = "A"\nDIM A(3)\nA(2) = 5\nM1 = 2\nJ1 = (0,0,90,0,90,0)\nEND\n')
    d.break_line(5)
    d.run()
    d.poll()
    d.step()
    d.poll()
    rows = {v.name: v for v in d.variables()}
    assert rows["M1"].value == "2" and rows["M1"].changed
    assert rows["S$"].value == '"A"' and not rows["S$"].changed
    assert rows["A"].kind is VarKind.ARRAY and rows["A"].elements[0].name == "A(2)"
    assert rows["P1"].kind is VarKind.POSITION
    d.step()
    d.poll()
    rows = {v.name: v for v in d.variables()}
    assert rows["J1"].changed and not rows["M1"].changed
    assert rows["J1"].value == melfa_text(Joints.from_degrees((0, 0, 90, 0, 90, 0)))
    assert {"P_CURR", "J_CURR", "M_OVRD", "M_SPD"} <= set(rows)


def test_print_reports_mistakes_plainly() -> None:
    d, _ = make("M1 = 1\nEND\n")
    d.run()
    d.poll()
    assert d.evaluate("M1 * 2, P1.X") == "2, 400"
    with pytest.raises(DebugError, match="variable M7 has no value"):
        d.evaluate("M7")
    with pytest.raises(DebugError, match="cannot read 'M1 \\+'"):
        d.evaluate("M1 +")


def test_numbered_programs_keep_their_own_numbers() -> None:
    d, _ = make("100 M1 = 1\n200 GOSUB 400\n300 END\n400 M2 = 2\n500 RETURN\n")
    d.break_line(4)
    d.run()
    stop = d.poll()
    assert stop is not None and (stop.location.line, stop.location.step) == (4, 400)


def test_programs_that_cannot_load_are_refused_in_words() -> None:
    with pytest.raises(DebugError, match="there is no step 99"):
        make("GOTO 99\n")
    with pytest.raises(DebugError, match="points line 1"):
        make("END\n", points="DEF POS P1=(1,2\n")


def test_status_is_json() -> None:
    d, _ = make(SUBS)
    d.break_label("SUB")
    d.run()
    d.poll()
    data = d.status().to_json()
    assert data["state"] == "paused" and data["speed"] == "instant"
    assert data["stop"]["reason"] == "breakpoint"  # type: ignore[index]
    assert data["location"] == {"line": 8, "step": 80, "source": "*SUB"}


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(min_value=-50, max_value=50), min_size=1, max_size=12))
def test_stepping_a_straight_program_visits_every_line_in_order(values: list[int]) -> None:
    text = "".join(f"M{i} = {v}\n" for i, v in enumerate(values, start=1)) + "END\n"
    d, _ = make(text)
    d.break_line(1)
    d.run()
    d.poll()
    seen = [line(d)]
    for _ in values:
        d.step()
        d.poll()
        seen.append(line(d))
    assert seen == list(range(1, len(values) + 2))
    assert d.evaluate(f"M{len(values)}") == str(values[-1])


def test_an_endless_loop_that_never_moves_stops_as_busy_and_polls_stay_short() -> None:
    d, _ = make("M1 = 0\n*L\nM1 = M1 + 1\nGOTO *L\n")
    d.run()
    polls = 0
    stop = None
    while stop is None:
        stop = d.poll()
        polls += 1
    assert stop.reason is StopReason.BUSY and polls > 1  # each poll gave control back
    assert stop.location.line in (2, 3, 4) and d.state is RunState.PAUSED
    d.step()
    assert d.poll() is not None  # it can still be stepped


def test_steps_are_watched_only_when_something_could_stop_there() -> None:
    d, _ = make(SUBS)
    d.run()
    assert d.interp.break_before is None  # continue, no breakpoints: full speed
    bp = d.break_line(9)
    assert d.interp.break_before is not None
    d.delete(bp.id)
    assert d.interp.break_before is None


def test_step_after_a_pause_mid_move_finishes_that_move_and_stops_at_the_next_line() -> None:
    d, clock = make("SERVO ON\nOVRD 10\nMOV P1\nM1 = 1\nEND\n", speed=REAL_TIME)
    d.run()
    clock.t = 0.3
    d.poll()
    stop = d.pause()
    assert stop is not None and stop.location.line == 3
    d.set_speed(INSTANT)
    d.step()
    stop = d.poll()
    assert stop is not None and stop.reason is StopReason.STEP and line(d) == 4
    assert d.evaluate("P_CURR") == melfa_text(
        Position.from_degrees((400, 100, 500, 180, 0, 180), 7, 0)
    )


def test_pause_in_a_wait_and_run_again_from_the_start() -> None:
    d, clock = make("M1 = 1\nWAIT M_IN(2) = 1\nM1 = 2\nEND\n", speed=REAL_TIME)
    d.run()
    clock.t = 1.0
    assert d.poll() is None and d.waiting
    stop = d.pause()
    assert stop is not None and stop.reason is StopReason.PAUSE and stop.location.line == 2
    assert d.pause() is None  # not running any more
    d.set_input(2, 1)
    d.continue_()
    clock.t = 2.0
    assert d.poll() is not None and d.evaluate("M1") == "2"
    d.run()
    assert d.state is RunState.RUNNING and d.time == 0.0
