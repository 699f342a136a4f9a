"""Programs that move the simulated RV-6S: the thesis sample, a pyramid stacker, motion
errors, STOP/RUN/RSTPRG, HLT, WAIT, interrupts, EXEC, real-time stepping."""

from __future__ import annotations

import math

import pytest

from melfa.kin import Pose, fk, pose_mul
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.fast import SLICE_S, run_fast, simulate
from melfa.sim.interp.interpreter import STEP_TIME_S, Interpreter
from melfa.sim.interp.io import IOState
from melfa.sim.runner import ProgramRunner, RunnerStatus, StatementExecutor
from melfa.sim.trajectory import HandState

THESIS_PROGRAM = """10 SERVO ON
20 SPD 20
30 OVRD 20
40 MOV Pa
50 MOV Pb
60 HOPEN 1
70 END
"""
THESIS_POINTS = {
    "PA": "Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)",
    "PB": "Pb=(225.48,-363.55,683.37,-128.32,2.12,-123.50)(7,0)",
}
PA = Pose(584.73, 141.04, 385.25, -163.74, 1.11, -78.61)
PB = Pose(225.48, -363.55, 683.37, -128.32, 2.12, -123.50)


def assert_at(pose: Pose, expected: Pose, tol: float = 0.01) -> None:
    assert (pose.x, pose.y, pose.z) == pytest.approx((expected.x, expected.y, expected.z), abs=tol)
    for got, want in zip(pose.abc, expected.abc, strict=True):
        assert math.remainder(got - want, 360.0) == pytest.approx(0.0, abs=tol)


def make(text: str, points: dict[str, str] | None = None, **kw: object) -> Interpreter:
    arm = SimulatedArm()
    it = Interpreter(ArmPort(arm), kw.get("io"))  # type: ignore[arg-type]
    it.load(text, points or {})
    return it


def arm_of(it: Interpreter) -> SimulatedArm:
    port = it.robot
    assert isinstance(port, ArmPort)
    return port.arm


# --- the thesis sample ------------------------------------------------------------------------


def test_interpreter_implements_the_controller_protocols() -> None:
    it = make("10 END\n")
    assert isinstance(it, ProgramRunner)
    assert isinstance(it, StatementExecutor)


def test_thesis_sample_program_reaches_pa_then_pb_and_opens_the_hand() -> None:
    r = simulate(THESIS_PROGRAM, THESIS_POINTS)
    assert r.interp.error is None
    assert r.interp.status is RunnerStatus.FINISHED
    moves = r.arm.recorder.moves
    assert [m.line for m in moves] == [40, 50]
    assert_at(fk(moves[0].plan.end_joints), PA)
    assert_at(r.arm.pose, PB)
    assert r.arm.hands[0] is HandState.OPEN
    (event,) = r.arm.recorder.hand_events
    assert (event.hand, event.line) == (1, 60)
    assert r.end_time - 2 * STEP_TIME_S - SLICE_S <= event.time < r.end_time  # the last


def test_points_uploaded_after_the_steps_are_program_variables() -> None:
    text = THESIS_PROGRAM + "".join(line + "\n" for line in THESIS_POINTS.values())
    r = simulate(text)
    assert r.interp.status is RunnerStatus.FINISHED
    assert_at(r.arm.pose, PB)


def test_speeds_reset_at_end() -> None:
    r = simulate(THESIS_PROGRAM, THESIS_POINTS)
    assert r.arm.speeds.ovrd == 100.0  # OVRD 20 is undone by END [S1 END]


# --- pyramid stacking ------------------------------------------------------------------------

PYRAMID = """10 SERVO ON
20 OVRD 50
30 MW = 40
40 MH = 30
50 MN = 0
60 FOR ML = 0 TO 2
70 FOR MK = 0 TO 2 - ML
80 GOSUB *PICK
90 PT = PBASE + (MK * MW + ML * MW / 2, 0, ML * MH, 0, 0, 0)
100 GOSUB *PLACE
110 MN = MN + 1
120 NEXT MK
130 NEXT ML
140 MOV PHOME
150 END
160 *PICK
170 MOV PFEED, -50
180 HOPEN 1
190 MVS PFEED
200 HCLOSE 1
210 MVS , -50
220 RETURN
230 *PLACE
240 MOV PT, -50
250 MVS PT
260 HOPEN 1
270 MVS PT, -50
280 RETURN
"""
PYRAMID_POINTS = [
    "PBASE=(350,-100,300,180,0,180)(7,0)",
    "PFEED=(350,200,300,180,0,180)(7,0)",
    "PHOME=(300,0,500,180,0,180)(7,0)",
]


def test_pyramid_places_six_blocks_where_the_offsets_say() -> None:
    r = simulate(PYRAMID, PYRAMID_POINTS)
    assert r.interp.error is None
    assert r.interp.status is RunnerStatus.FINISHED
    assert r.interp.state.vars["MN"] == 6
    assert_at(r.arm.pose, Pose(300, 0, 500, 180, 0, 180))
    assert r.arm.hands[0] is HandState.OPEN
    # expected drop points, computed from the base point and the block size
    expected = [
        (350 + mk * 40 + ml * 20, -100, 300 + ml * 30) for ml in range(3) for mk in range(3 - ml)
    ]
    samples = r.arm.recorder.samples
    drops = [
        s.pose
        for e in r.arm.recorder.hand_events
        if e.line == 260
        for s in samples
        if s.time == e.time and s.line == 260
    ]
    assert len(drops) == 6
    for pose, xyz in zip(drops, expected, strict=True):
        assert (pose.x, pose.y, pose.z) == pytest.approx(xyz, abs=0.01)
    closes = [e for e in r.arm.recorder.hand_events if e.state is HandState.CLOSED]
    assert len(closes) == 6 and all(e.line == 200 for e in closes)


def test_close_distance_is_along_tool_z() -> None:
    r = simulate("10 SERVO ON\n20 MOV P1, -50\n30 END\n", ["P1=(400,0,400,180,0,180)(7,0)"])
    # hand pointing down: retracting 50 mm along tool Z goes up in world Z
    assert_at(r.arm.pose, Pose(400, 0, 450, 180, 0, 180))


def test_mvs_offset_and_tool_frame_multiplication() -> None:
    r = simulate(
        "10 SERVO ON\n20 MOV P1\n30 MVS , 20\n40 M1 = P_CURR.Z\n"
        "50 MOV P1 * (10, 0, 0, 0, 0, 0)\n60 END\n",
        ["P1=(400,0,400,180,0,180)(7,0)"],
    )
    assert r.interp.state.vars["M1"] == pytest.approx(380.0, abs=0.01)
    expected = pose_mul(Pose(400, 0, 400, 180, 0, 180), Pose(10, 0, 0, 0, 0, 0))
    assert_at(r.arm.pose, expected)


def test_joint_targets_and_j_curr() -> None:
    r = simulate(
        "10 SERVO ON\n20 J1 = (10, 0, 90, 0, 90, 0)\n30 MOV J1\n40 M1 = DEG(J_CURR.J1)\n50 END\n"
    )
    assert r.interp.state.vars["M1"] == pytest.approx(10.0)


def test_arc_and_arch_moves_end_where_they_should() -> None:
    points = [
        "P1=(400,-50,400,180,0,180)(7,0)",
        "P2=(450,0,400,180,0,180)(7,0)",
        "P3=(400,50,400,180,0,180)(7,0)",
    ]
    r = simulate("10 SERVO ON\n20 MVR P1, P2, P3\n30 END\n", points)
    assert r.interp.error is None
    assert_at(r.arm.pose, Pose(400, 50, 400, 180, 0, 180))
    r = simulate("10 SERVO ON\n20 MVC P1, P2, P3\n30 END\n", points)
    assert_at(r.arm.pose, Pose(400, -50, 400, 180, 0, 180))
    r = simulate("10 SERVO ON\n20 MOV P1\n30 MVA P3\n40 END\n", points)
    assert_at(r.arm.pose, Pose(400, 50, 400, 180, 0, 180))


def test_wth_applies_at_the_start_of_the_move() -> None:
    io = IOState()
    r = simulate(
        "10 SERVO ON\n20 MOV P1 WTH M_OUT(5) = 1\n30 END\n",
        ["P1=(400,0,400,180,0,180)(7,0)"],
        io=io,
    )
    assert io.output(5) == 1
    assert r.interp.status is RunnerStatus.FINISHED


def test_wthif_skip_stops_the_move_when_the_input_comes() -> None:
    io = IOState()
    it = make(
        "10 SERVO ON\n20 MOV P1 WTHIF M_IN(3) = 1, SKIP\n30 M1 = M_SKIPCQ\n40 END\n",
        {"P1": "P1=(400,0,300,180,0,180)(7,0)"},
        io=io,
    )
    it.start(0.0)
    it.advance(0.05)
    assert arm_of(it).is_moving()
    io.set_input(3, 1)
    it.advance(0.1)
    run_fast(it, max_time=10)
    assert it.status is RunnerStatus.FINISHED
    assert it.state.vars["M1"] == 1
    assert arm_of(it).pose.z > 300.5  # stopped before the target


# --- motion errors ---------------------------------------------------------------------------


def failed(text: str, points: list[str] | None = None) -> tuple[int, int | None, errors.ErrorLevel]:
    r = simulate(text, points or [])
    assert r.interp.status is RunnerStatus.FAILED
    err = r.interp.error
    assert err is not None
    return err.number, err.line, err.level


def test_joint_limit_stops_with_h2160_and_servo_off() -> None:
    number, line, level = failed("10 SERVO ON\n20 J1 = (0, 150, 90, 0, 90, 0)\n30 MOV J1\n40 END\n")
    assert (number, line, level) == (errors.JOINT_LIMIT, 30, errors.ErrorLevel.HIGH)


def test_unreachable_point_stops_with_the_arms_number() -> None:
    number, line, _ = failed("10 SERVO ON\n20 MOV P1\n30 END\n", ["P1=(2000,0,300,180,0,180)(7,0)"])
    assert (number, line) == (2600, 20)


def test_undefined_point_is_l3700() -> None:
    number, line, _ = failed("10 SERVO ON\n20 MOV PNOWHERE\n30 END\n")
    assert (number, line) == (errors.UNDEFINED_VARIABLE, 20)


def test_moving_with_servo_off_is_l2000() -> None:
    number, line, _ = failed("10 MOV P1\n20 END\n", ["P1=(400,0,400,180,0,180)(7,0)"])
    assert (number, line) == (errors.SERVO_OFF, 10)


def test_bad_speed_values() -> None:
    assert failed("10 OVRD 0\n20 END\n")[:2] == (errors.ARGUMENT_OUT_OF_RANGE, 10)
    assert failed("10 OVRD 50\n20 HOPEN 9\n")[:2] == (errors.ARGUMENT_OUT_OF_RANGE, 20)


# --- real time, STOP / RUN / RSTPRG, HLT, WAIT ----------------------------------------------


def test_real_time_move_blocks_until_its_end() -> None:
    it = make(
        "10 SERVO ON\n20 MOV P1\n30 M1 = 1\n40 END\n", {"P1": "P1=(400,0,300,180,0,180)(7,0)"}
    )
    it.start(0.0)
    it.advance(STEP_TIME_S)  # SERVO ON took its step time; the move starts
    end = arm_of(it).motion_end()
    assert end is not None and end > 0.1
    it.advance(end / 2)
    assert it.line == 20
    assert "M1" not in it.state.vars
    it.advance(end + STEP_TIME_S)  # the move, then M1 = 1's step time; END runs then
    assert it.status is RunnerStatus.FINISHED
    assert it.state.vars["M1"] == 1


def test_dly_waits_simulated_seconds() -> None:
    it = make("10 DLY 0.5\n20 M1 = 1\n30 END\n")
    it.start(0.0)
    it.advance(0.4)
    assert (it.line, "M1" in it.state.vars) == (10, False)
    it.advance(0.5)
    assert it.state.vars["M1"] == 1


def test_stop_pauses_and_run_resumes_the_interrupted_move() -> None:
    it = make(
        "10 SERVO ON\n20 OVRD 30\n30 MOV P1\n40 M1 = 1\n50 END\n",
        {"P1": "P1=(400,0,300,180,0,180)(7,0)"},
    )
    it.start(0.0)
    it.advance(0.2)
    it.pause(0.2)
    assert it.status is RunnerStatus.PAUSED
    assert it.line == 30
    arm = arm_of(it)
    stop_end = arm.motion_end()
    assert stop_end is not None
    it.advance(stop_end + 1.0)
    assert not arm.is_moving()
    assert it.status is RunnerStatus.PAUSED
    assert "M1" not in it.state.vars
    it.resume(stop_end + 1.0)
    run_fast(it)
    assert it.status is RunnerStatus.FINISHED
    assert_at(arm.pose, Pose(400, 0, 300, 180, 0, 180))
    assert it.state.vars["M1"] == 1


def test_rstprg_resets_line_variables_and_speeds() -> None:
    it = make("10 SERVO ON\n20 OVRD 30\n30 M1 = 5\n40 DLY 10\n50 END\n")
    it.start(0.0)
    it.advance(1.0)
    it.pause(1.0)
    assert arm_of(it).speeds.ovrd == 30.0
    it.reset()
    assert it.status is RunnerStatus.IDLE
    assert it.line == 10
    assert "M1" not in it.state.vars
    assert arm_of(it).speeds.ovrd == 100.0


def test_hlt_pauses_and_run_continues_at_the_next_line() -> None:
    it = make("10 M1 = 1\n20 HLT\n30 M1 = 2\n40 END\n")
    it.start(0.0)
    run_fast(it)
    assert (it.status, it.line, it.state.vars["M1"]) == (RunnerStatus.PAUSED, 20, 1)
    it.resume(1.0)
    run_fast(it)
    assert (it.status, it.state.vars["M1"]) == (RunnerStatus.FINISHED, 2)


def test_wait_blocks_until_the_input_and_shows_waiting() -> None:
    io = IOState()
    it = make("10 WAIT M_IN(3) = 1\n20 M1 = 5\n30 END\n", io=io)
    it.start(0.0)
    it.advance(0.0)
    it.advance(5.0)
    assert it.waiting
    assert it.line == 10
    io.set_input(3, 1)
    it.advance(5.1)  # WAIT sees the input; M1 = 5 takes one step time
    it.advance(5.1 + STEP_TIME_S)  # END
    assert not it.waiting
    assert it.status is RunnerStatus.FINISHED


def test_runaway_loop_does_not_freeze_the_controller() -> None:
    it = make("10 M1 = M1 + 1\n20 GOTO 10\n")
    it.set_point("M1", 0)
    it.start(0.0)
    it.advance(0.0)
    assert it.status is RunnerStatus.RUNNING
    first = it.state.vars["M1"]
    assert isinstance(first, int) and 0 < first <= it.max_statements
    it.advance(1.0)  # one step per STEP_TIME_S of program time: about 70 passes a second
    passes = it.state.vars["M1"] - first  # type: ignore[operator]
    assert passes == pytest.approx(1.0 / STEP_TIME_S / 2, abs=2)


def test_cycle_false_repeats_the_program() -> None:
    it = make("10 M1 = M1 + 1\n20 END\n")
    it.set_point("M1", 0)
    it.start(0.0, cycle=False)
    it.advance(0.1)
    assert it.status is RunnerStatus.RUNNING
    assert it.state.vars["M1"] > 1  # type: ignore[operator]


# --- interrupts and EXEC ------------------------------------------------------------------------


def test_def_act_interrupt_gosub_and_return() -> None:
    io = IOState()
    it = make(
        "10 DEF ACT 1, M_IN(5) = 1 GOSUB *HIT\n20 ACT 1 = 1\n30 M2 = 0\n"
        "40 DLY 1\n50 IF M2 = 0 THEN 40\n60 END\n"
        "70 *HIT\n80 M2 = 1\n90 ACT 1 = 0\n100 RETURN 1\n",
        io=io,
    )
    it.start(0.0)
    it.advance(0.5)
    it.advance(2.5)
    assert it.status is RunnerStatus.RUNNING
    io.set_input(5, 1)
    it.advance(2.6)
    it.advance(4.0)
    assert it.status is RunnerStatus.FINISHED
    assert it.state.vars["M2"] == 1


def test_execute_runs_one_statement_in_the_slot_variables() -> None:
    it = make("10 M1 = 2\n20 END\n")
    it.start(0.0)
    run_fast(it)
    it.execute("M3 = M1 * 21", 1.0)
    assert it.state.vars["M3"] == 42
    it.execute("SERVO ON", 1.0)
    it.execute("P9 = (400, 0, 400, 180, 0, 180)(7, 0)", 1.0)
    it.execute("MOV P9", 1.0)
    arm = arm_of(it)
    assert arm.is_moving(1.0)
    with pytest.raises(errors.RunError) as info:
        it.execute("GOTO 10", 1.0)
    assert info.value.number == errors.SYNTAX_ERROR
    with pytest.raises(errors.RunError) as info:
        it.execute("M4 = M_UNSET + 1", 1.0)
    assert info.value.number == errors.UNDEFINED_VARIABLE
