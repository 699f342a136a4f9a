"""Programs on the virtual controller: shared I/O, WAIT and error status in STATE, EXEC
through the interpreter, and program timing that does not depend on how often we poll."""

from __future__ import annotations

import pytest

from melfa.protocol.answers import DState, Position, State
from melfa.protocol.messages import Ok
from melfa.sim import VirtualController
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.interpreter import STEP_TIME_S, Interpreter
from melfa.sim.machine import SimArm
from melfa.sim.runner import RunnerStatus
from melfa.sim.trajectory import HandState
from tests.fixtures_sim import Driver


def upload(drive: Driver, name: str, program: str, *points: str) -> None:
    drive.ok("NEW")
    drive.ok(f"LOAD={name}")
    for item in [*program.strip().splitlines(), *points]:
        drive.ok("EMDAT" + item)
    drive.ok("SAVE")


def state(drive: Driver) -> State:
    return State.parse(drive.send("STATE")[3:-1].decode())


def sim_arm(controller: VirtualController) -> SimulatedArm:
    assert isinstance(controller.arm, SimArm)
    return controller.arm.arm


# ------------------------------------------------------------------------------ I/O, WAIT


def test_an_input_set_on_the_controller_releases_a_waiting_program(ready: Driver) -> None:
    upload(ready, "W", "10 WAIT M_IN(3) = 1\n20 M_OUT(5) = 1\n30 END")
    ready.ok("RUNW;1")
    ready.wait(2.0)
    waiting = state(ready)
    assert waiting.line == 10
    assert waiting.status.run & 0x40 and waiting.status.stop == 0x04  # RUN + WAIT
    assert DState.parse(ready.ok("DSTATE")).status.stop == 0x04
    ready.controller.set_input(3, 1)
    assert ready.ok("IN0") == "0008"
    ready.wait(0.1)
    done = state(ready)
    assert not done.status.run & 0x40 and not done.status.stop & 0x04
    assert ready.ok("OUT0") == "0020"  # the program's M_OUT(5)


def test_exec_and_programs_share_one_io(ready: Driver) -> None:
    ready.ok("EXECM_OUT(2) = 1")  # EXEC with no program selected
    assert ready.controller.io.output(2) == 1
    ready.ok("OUT=8;00FF")
    assert ready.ok("OUT8") == "00FF"
    upload(ready, "R", "10 IF M_OUT(2) + M_IN(0) = 2 THEN M_OUT(20) = 1\n20 END")
    ready.controller.set_input(0, 1)
    ready.ok("RUNR;1")
    ready.wait(0.1)
    assert ready.controller.io.output(20) == 1


def test_io_commands_refuse_garbage(ready: Driver) -> None:
    assert ready.send("INX") == b"QeR601000000\r"
    assert ready.send("OUT=3;ZZZZ") == b"QeR601000000\r"


# ----------------------------------------------------------------------------- STATE lines


def test_state_follows_the_running_line(ready: Driver) -> None:
    upload(ready, "L", "10 DLY 1\n20 DLY 1\n30 END")
    ready.ok("RUNL;1")
    ready.wait(0.5)
    assert state(ready).line == 10
    ready.wait(1.0)
    running = state(ready)
    assert running.line == 20 and running.status.run & 0x40 and running.status.stop == 0
    assert DState.parse(ready.ok("DSTATE")).step == 20


def test_a_run_time_error_shows_number_and_line_in_state_error_and_log(ready: Driver) -> None:
    upload(ready, "E", "10 M1 = 1\n20 DLY 0.2\n30 M2 = M9 + 1\n40 END")
    ready.ok("RUNE;1")
    ready.wait(1.0)
    failed = state(ready)
    assert (failed.line, failed.status.error) == (30, 3700)
    assert not failed.status.run & 0x40 and failed.status.stop & 0x02
    assert ready.send("ERROR") == b"Qok3700;2\r"
    fields = ready.send("ERRORLOGTOP").decode().split(";")
    assert fields[2:7] == ["3700", "Undefined (uninitialised) variable", "2", "E", "30"]


def test_a_user_error_keeps_its_level_and_text(ready: Driver) -> None:
    upload(ready, "U", "10 ERROR 9050\n20 END")
    assert ready.send("RUNU;1") == b"Qok\r"  # fails at its first step
    ready.wait(0.1)
    assert ready.send("ERROR") == b"Qok9050;1\r"  # 9000-9099 are H level [S1 ERROR]
    fields = ready.send("ERRORLOGTOP").decode().split(";")
    assert fields[2:4] == ["9050", "user error 9050"]


# ------------------------------------------------------------------------------------ EXEC


def test_a_comment_is_accepted_by_the_interpreter_itself() -> None:
    it = Interpreter(ArmPort(SimulatedArm()))
    it.execute("REM Waiting...", 0.0)
    it.execute("' nothing to do", 0.0)
    with pytest.raises(errors.RunError) as info:
        it.execute("", 0.0)
    assert info.value.number == errors.SYNTAX_ERROR


def test_exec_comment_through_the_controller(ready: Driver) -> None:
    assert ready.send("EXECREM Waiting...") == b"QoK\r"
    assert ready.send("EXEC' also fine") == b"QoK\r"


def joints(drive: Driver) -> list[float]:
    answer = Position.parse(drive.ok("JPOSF"))
    return [answer[f"J{i}"] or 0.0 for i in range(1, 7)]


def test_exec_joint_plus_a_constant_is_a_joint_move(ready: Driver) -> None:
    before = joints(ready)
    ready.ok("EXECMOV J_CURR+(0,0,5,0,0,0)")
    ready.wait(3)
    after = joints(ready)
    assert after[2] == pytest.approx(before[2] + 5, abs=0.01)
    assert after[:2] == pytest.approx(before[:2], abs=0.01)
    ready.ok("EXECMOV J_CURR-(0,0,5,0,0,0)")
    ready.wait(3)
    assert joints(ready) == pytest.approx(before, abs=0.01)


def test_exec_position_times_a_constant_moves_in_the_tool_frame(ready: Driver) -> None:
    z0 = Position.parse(ready.ok("PPOSF"))["Z"]
    assert z0 is not None
    ready.ok("EXECMOV P_CURR*(0,0,-50,0,0,0)")  # hand down: tool -Z is world +Z
    ready.wait(3)
    assert Position.parse(ready.ok("PPOSF"))["Z"] == pytest.approx(z0 + 50, abs=0.01)


# ---------------------------------------------------------------------------------- timing


LOOP = "10 FOR M1 = 1 TO 1500\n20 DLY 0.01\n30 NEXT M1\n40 HOPEN 1\n50 END"


def test_program_timing_does_not_depend_on_polling(ready: Driver) -> None:
    """3000 statements and 1500 DLYs between two polls: the hand still opens at 15 s."""
    start = ready.now
    upload(ready, "T", LOOP)
    ready.ok("RUNT;1")
    ready.wait(100)
    assert not state(ready).status.run & 0x40
    (event,) = sim_arm(ready.controller).recorder.hand_events
    assert event.state is HandState.OPEN
    # 1500 DLYs of 0.01 s, and FOR and 1500 NEXTs of one step time each
    assert event.time - start == pytest.approx(15.0 + 1501 * STEP_TIME_S, abs=1e-6)


def test_one_interpreter_advance_keeps_the_timing_of_many_steps() -> None:
    arm = SimulatedArm()
    it = Interpreter(ArmPort(arm))
    it.load(LOOP)
    it.start(0.0, cycle=True)
    it.advance(100.0)
    assert it.status is RunnerStatus.FINISHED
    (event,) = arm.recorder.hand_events
    assert event.time == pytest.approx(15.0 + 1501 * STEP_TIME_S, abs=1e-6)


def test_dly_after_dly_in_one_poll(ready: Driver) -> None:
    upload(ready, "D", "10 DLY 0.5\n20 DLY 0.5\n30 HOPEN 1\n40 END")
    start = ready.now
    ready.ok("RUND;1")
    ready.wait(10)
    assert isinstance(ready.reply("STATE"), Ok)
    (event,) = sim_arm(ready.controller).recorder.hand_events
    assert event.time - start == pytest.approx(1.0)
