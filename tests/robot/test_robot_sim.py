"""The robot client against the virtual controller through a real pty at 9600 8E2."""

from __future__ import annotations

import threading

import pytest

from melfa.link import LinkClosed, LinkError, SerialLink
from melfa.protocol import (
    JOINT_NAMES,
    POSE_NAMES,
    JogMode,
    Ok,
    Refused,
    Request,
    RunStatus,
    error_text,
)
from melfa.protocol.error_table import DURING_ERROR
from melfa.robot import (
    ControllerError,
    JogMethod,
    Robot,
    RobotSettings,
    Stopped,
    UploadRefused,
)
from melfa.sim import PtyServer, SimConfig, VirtualController
from tests.plans import points_plan, program_plan, project
from tests.robot.conftest import LINK
from tests.waiting import wait_until

NUMBERED = "10 SERVO ON\n20 MOV P1\n30 HOPEN 1\n40 END\n"
UNNUMBERED = "SERVO ON\nMOV P1\n\nHCLOSE 1\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,450.00,180.00,0.00,180.00)(7,0)\n"


def stored(controller: VirtualController) -> dict[int, str]:
    program = controller.store.get("1")
    assert program is not None
    return dict(program.lines)


def test_upload_numbered_program(robot: Robot, controller: VirtualController) -> None:
    report = robot.upload_program(program_plan(NUMBERED))
    assert report.requests == 1
    assert stored(controller) == {
        10: "10 SERVO ON",
        20: "20 MOV P1",
        30: "30 HOPEN 1",
        40: "40 END",
    }
    assert controller.edit is None


def test_upload_unnumbered_program_is_numbered(robot: Robot, controller: VirtualController) -> None:
    robot.upload_program(program_plan(UNNUMBERED))
    assert list(stored(controller).values()) == [
        "10 SERVO ON",
        "20 MOV P1",
        "40 HCLOSE 1",
        "50 END",
    ]


def test_upload_replaces_old_lines(robot: Robot, controller: VirtualController) -> None:
    robot.upload_program(program_plan("10 SERVO ON\n20 MOV P1\n30 MOV P2\n40 END"))
    robot.upload_program(program_plan("10 SERVO OFF\n20 END"))
    assert stored(controller) == {10: "10 SERVO OFF", 20: "20 END"}


def test_points_and_project(robot: Robot, controller: VirtualController) -> None:
    report = robot.load_project(project(NUMBERED, POINTS))
    program = controller.store.get("1")
    assert program is not None
    assert list(program.positions) == ["P1"]
    assert program.positions["P1"].startswith("P1=(300.00,0.00,450.00")
    assert report.requests == 1
    robot.upload_points(points_plan(["P2=(1,2,3,4,5,6)(7,0)"]))
    program = controller.store.get("1")
    assert program is not None and set(program.positions) == {"P1", "P2"}
    assert len(program.lines) == 4  # points alone keep the steps


def test_long_program_needs_several_emdat_and_arrives_line_by_line(
    robot: Robot, controller: VirtualController
) -> None:
    lines = [f"{10 * i} MOV P{i % 7 + 1}" for i in range(1, 201)] + ["2010 END"]
    progress: list[tuple[int, int]] = []
    report = robot.upload_program(
        program_plan(lines), progress=lambda a, b: progress.append((a, b))
    )
    assert report.requests > 5
    assert [text for _, text in sorted(stored(controller).items())] == lines
    totals = {total for _, total in progress}
    assert len(totals) == 1 and progress[0][0] == 0 and progress[-1][0] == totals.pop()
    assert [sent for sent, _ in progress] == sorted(sent for sent, _ in progress)


def test_run_and_wait(robot: Robot, controller: VirtualController) -> None:
    robot.load_project(project("10 SERVO ON\n20 MOV P1\n30 END", POINTS))
    robot.run()
    state = robot.wait_idle(timeout=30)
    assert RunStatus.RUNNING not in state.status.run
    assert robot.state().status.error == 0


def test_delete_program_and_points(robot: Robot, controller: VirtualController) -> None:
    robot.load_project(project(NUMBERED, POINTS))
    robot.delete()
    assert "1" not in controller.store
    robot.delete()  # nothing left: still fine


def test_exec_pose_and_joints(robot: Robot, controller: VirtualController) -> None:
    before = robot.joints().values(*JOINT_NAMES)
    robot.servo(True)
    robot.exec("JT=(10,0,0,0,0,0)")
    robot.exec("MOV J_CURR+JT")
    robot.wait_idle(timeout=60)
    wait_until(lambda: not controller.moving)
    after = robot.joints().values(*JOINT_NAMES)
    assert after[0] == pytest.approx(before[0] + 10, abs=0.01)
    pose = robot.pose()
    assert len(pose.values(*POSE_NAMES)) == 6 and pose.fl1 is not None


def test_override_and_hand(robot: Robot, controller: VirtualController) -> None:
    assert robot.override(30) == 30
    robot.servo(True)
    robot.hand(True, 1)
    robot.hand(False, 1)
    with pytest.raises(Exception, match="outside 1–100"):
        robot.override(0)


@pytest.mark.usefixtures("not_strict")  # continuous JOG: documented only
def test_jog_start_and_stop(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    assert robot.jog(JogMode.JOINT, 0, +1) is JogMethod.JOG
    assert controller.moving  # the simulator advances only on requests: no race here
    robot.jog_stop()
    assert not controller.moving


@pytest.mark.parametrize("sim_config", [SimConfig(jog_supported=False)])
def test_jog_falls_back_to_steps_and_remembers(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    robot.override(1)  # a slow step, so the second call surely finds it still moving
    start = robot.joints().values("J1")[0]
    assert robot.jog(JogMode.JOINT, 0, +1) is JogMethod.STEP
    assert robot.jog_method is JogMethod.STEP
    assert robot.jog(JogMode.JOINT, 0, +1) is JogMethod.STEP  # busy: skipped, not queued
    robot.wait_idle(timeout=120)
    assert robot.joints().values("J1")[0] == pytest.approx(start + robot.settings.jog_step_deg)


def test_stop_during_motion(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    robot.override(2)  # the 90° move takes many seconds: STOP surely lands mid-move
    robot.exec("JT=(90,0,0,0,0,0)")
    robot.exec("MOV J_CURR+JT")
    assert controller.moving
    robot.stop()
    robot.wait_idle(timeout=60)
    assert robot.joints().values("J1")[0] < 90


def test_stop_from_another_thread_interrupts_wait(
    robot: Robot, controller: VirtualController
) -> None:
    robot.servo(True)
    robot.override(5)
    robot.exec("JT=(120,0,0,0,0,0)")
    robot.exec("MOV J_CURR+JT")
    errors: list[BaseException] = []

    def worker() -> None:
        try:
            robot.wait_idle(timeout=60, poll=0.1)
        except BaseException as exc:
            errors.append(exc)

    thread = threading.Thread(target=worker)
    thread.start()
    wait_until(lambda: robot.channel.received_replies > 5, 30)
    robot.stop()
    thread.join(timeout=60)
    assert not thread.is_alive()
    assert (errors and isinstance(errors[0], Stopped)) or not controller.moving


# ---------------------------------------------------------------------- refusals


def test_unknown_command_is_6010_and_state_is_answered_before_open(
    robot: Robot, controller: VirtualController
) -> None:
    # Real controllers answered clients that never sent OPEN (SimConfig.open_required).
    assert isinstance(robot.channel.request(Request("STATE")), Ok)
    with pytest.raises(ControllerError) as exc:
        robot.request("NOSUCHCOMMAND")
    assert exc.value.number == 6010
    assert "6010" in str(exc.value)


def test_6020_without_rights_and_rights_taken_again(
    robot: Robot, controller: VirtualController
) -> None:
    robot.connect()
    assert robot.channel.request(Request("SRVON")) == Refused(6020, detail="00000")
    robot.servo(True)  # takes CNTLON
    robot.request("CNTLOFF")  # rights lost behind the client's back
    robot.servo(True)  # 6020, CNTLON again, retried
    assert controller.arm.servo


def test_5640_while_moving(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    robot.override(5)
    robot.exec("JT=(60,0,0,0,0,0)")
    robot.exec("MOV J_CURR+JT")
    with pytest.raises(ControllerError) as exc:
        robot.exec("MOV J_CURR-JT")
    assert exc.value.number == 5640
    robot.stop()


def test_2160_beyond_joint_limit(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    robot.exec("JT=(500,0,0,0,0,0)")
    with pytest.raises(ControllerError) as exc:
        robot.exec("MOV J_CURR+JT")
    assert exc.value.number == 2160
    assert "Joint angle exceeds the limit" in exc.value.message


def test_4220_on_emdat_names_line_and_column(robot: Robot, controller: VirtualController) -> None:
    robot.upload_program(program_plan(NUMBERED))
    with pytest.raises(UploadRefused) as exc:
        robot.upload_program(program_plan("10 SERVO ON\n\n20 MOV P1\n30 FOO BAR(\n40 END"))
    assert (exc.value.number, exc.value.line, exc.value.text) == (4220, 4, "30 FOO BAR(")
    assert exc.value.column >= 1
    assert stored(controller)[20] == "20 MOV P1"  # the old program is intact
    assert controller.edit is None  # closed with NEW


@pytest.mark.parametrize("sim_config", [SimConfig(check_syntax_on_emdat=False)])
def test_4220_on_save_keeps_old_program(robot: Robot, controller: VirtualController) -> None:
    robot.upload_program(program_plan(NUMBERED))
    with pytest.raises(ControllerError) as exc:
        robot.upload_program(program_plan("10 SERVO ON\n20 FOO BAR(\n30 END"))
    assert exc.value.number == 4220 and exc.value.command == "SAVE"
    assert stored(controller) == {
        10: "10 SERVO ON",
        20: "20 MOV P1",
        30: "30 HOPEN 1",
        40: "40 END",
    }
    assert controller.edit is None


def test_link_loss_midway_through_upload_saves_nothing(
    controller: VirtualController,
) -> None:
    server = PtyServer(controller)
    robot = Robot(SerialLink(server.new_port(), LINK))
    lines = [f"{10 * i} MOV P1" for i in range(1, 150)]

    def pull_the_plug(sent: int, total: int) -> None:
        if 0 < sent < total:
            server.close()

    with pytest.raises(LinkError) as exc:
        robot.upload_program(program_plan(lines), progress=pull_the_plug)
    assert isinstance(exc.value, LinkClosed) or "in time" in str(exc.value)
    assert "1" not in controller.store
    robot.close()


def test_stop_needs_no_rights_and_works_before_anything(
    robot: Robot, controller: VirtualController
) -> None:
    robot.stop()
    assert robot.banner is not None


def test_client_name_setting(controller: VirtualController, pty_server: PtyServer) -> None:
    with Robot(SerialLink(pty_server.new_port(), LINK), RobotSettings(client_name="NARCUSR")) as r:
        r.connect()
        assert controller.client == "NARCUSR"


def test_pipelined_upload_same_result(controller: VirtualController, pty_server: PtyServer) -> None:
    lines = [f"{10 * i} MOV P{i % 7 + 1}" for i in range(1, 120)] + ["1200 END"]
    with Robot(SerialLink(pty_server.new_port(), LINK), RobotSettings(emdat_window=2)) as r:
        report = r.upload_program(program_plan(lines))
        assert report.requests > 3
        assert [text for _, text in sorted(stored(controller).items())] == lines
        with pytest.raises(UploadRefused) as exc:
            r.upload_program(program_plan([*lines[:4], "50 FOO(", *lines[5:]]))
        assert exc.value.line == 5  # refused while the next chunk was already in flight
        assert controller.edit is None
        r.upload_program(program_plan("10 END"))  # pairing intact after the refusal
        assert stored(controller) == {10: "10 END"}


# ---------------------------------------------------------------- alarms, status, reset

TOO_FAR = "MOV P_CURR*(0,0,-5000,0,0,0)"


def test_alarm_refusal_status_and_reset(robot: Robot, controller: VirtualController) -> None:
    robot.servo(True)
    with pytest.raises(ControllerError) as exc:
        robot.exec(TOO_FAR)
    assert exc.value.number == 2600 and exc.value.alarm
    assert str(exc.value) == f"the controller refused `{TOO_FAR}`: {error_text(2600)}"
    with pytest.raises(ControllerError) as during:
        robot.exec("OVRD 10")
    assert during.value.number == DURING_ERROR and during.value.alarm
    status = robot.status()
    assert status.alarm is not None and status.alarm.number == 2600
    assert status.alarm.detail == error_text(2600)
    assert status.servo_on and status.run_state == "stopped"
    assert robot.active_alarm() == status.alarm
    assert robot.reset_alarm() is None
    assert robot.status().alarm is None and not robot.alarm
    robot.exec("OVRD 10")  # accepted again


def test_status_of_a_running_program(robot: Robot, controller: VirtualController) -> None:
    robot.load_project(project("10 SERVO ON\n20 OVRD 5\n30 MOV P1\n40 END", POINTS))
    robot.run()
    status = robot.status()
    assert status.running and status.state.program.startswith("1")
    assert status.to_json()["run"] in ("running", "waiting") and status.alarm is None
    robot.stop()


def test_load_project_replaces_program_and_points(
    robot: Robot, controller: VirtualController
) -> None:
    """The thesis deleted slot 1 before loading; ECLR inside the edit does the same."""
    robot.load_project(
        project(
            "10 MOV P1\n20 MOV P2\n30 HOPEN 1\n40 END",
            [POINTS, "DEF POS P2=(300.00,50.00,450.00,180.00,0.00,180.00)(7,0)"],
        )
    )
    robot.load_project(
        project("10 MOV P3\n20 END", ["P3=(310.00,0.00,450.00,180.00,0.00,180.00)(7,0)"])
    )
    program = controller.store.get("1")
    assert program is not None
    assert list(program.lines.values()) == ["10 MOV P3", "20 END"]
    assert list(program.positions) == ["P3"]
