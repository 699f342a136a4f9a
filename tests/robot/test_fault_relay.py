"""Faults between the client and the virtual controller, through a real pty at 9600 8E2
(`tests.robot.relay.FaultRelay`): each gives a clear error, the right exit code, and never a
truncated or misaligned program saved."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.link import LinkError, LinkSettings, LinkTimeout, SerialLink
from melfa.robot import Robot, RobotError, SavedNotConfirmed, SaveOutcomeUnknown
from melfa.robot.channel import RepliesOutOfStep
from tests.plans import project
from tests.robot.relay import Fault, FaultRelay

PROMPT_S = 10.0
"""Reply timeout for requests that are answered (generous on a loaded machine)."""
SILENT_S = 0.6
"""Reply timeout in tests that wait for a request that is never answered."""

PROGRAM = "\n".join(f"{10 * i} MOV P{1 + i % 3}" for i in range(1, 41)) + "\n420 END\n"
POINTS = "\n".join(
    f"DEF POS P{i}=({300 + i}.00,{10 * i}.00,400.00,180.00,0.00,180.00)(7,0)" for i in (1, 2, 3)
)
OLD = "10 MOV P1\n20 END\n"
OLD_POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture
def relay() -> Iterator[FaultRelay]:
    made = FaultRelay()
    yield made
    made.close()


def robot_on(relay: FaultRelay, timeout: float = PROMPT_S) -> Robot:
    return Robot(SerialLink(relay.new_port(), LinkSettings(timeout=timeout)))


def held_program(relay: FaultRelay) -> list[str] | None:
    program = relay.controller.store.get("1")
    return None if program is None else [program.lines[n] for n in sorted(program.lines)]


def with_old_program(relay: FaultRelay) -> list[str]:
    """Upload the old program through the (still fault-free) relay; return its steps."""
    with robot_on(relay) as robot:
        robot.load_project(project(OLD, OLD_POINTS))
    old = held_program(relay)
    assert old == ["10 MOV P1", "20 END"]
    relay.lines.clear()
    return old


def test_an_unsolicited_reply_is_caught_and_the_session_resynchronises(relay) -> None:  # type: ignore[no-untyped-def]
    relay.add(Fault.extra_before("PPOSF", b"QoK\r"))
    with robot_on(relay) as robot:
        first = robot.joints().values("J1")
        with pytest.raises(RepliesOutOfStep, match="does not fit the request 'PPOSF'"):
            robot.pose()  # the stray QoK came first: it does not fit PPOSF
        # The real PPOSF answer is still coming; the next request resynchronises first.
        assert robot.joints().values("J1") == first
        assert robot.channel.resyncs == 1
        assert "PARRLNG" in relay.commands()


def test_a_late_reply_after_a_timeout_is_dropped_never_paired(relay) -> None:  # type: ignore[no-untyped-def]
    relay.add(Fault.late("STATE"))
    with robot_on(relay, SILENT_S) as robot:
        robot.connect()
        with pytest.raises(LinkTimeout, match="STATE"):
            robot.state()
        # The STATE answer arrives now, in front of the next reply: it must be dropped.
        position = robot.joints()
        assert position.values("J1", "J2") == (0.0, 0.0)
        assert robot.channel.dropped_replies == 1


def test_a_reply_to_another_request_is_an_error_not_data(relay) -> None:  # type: ignore[no-untyped-def]
    pose = b"QoKX;1.00;Y;2.00;Z;3.00;A;4.00;B;5.00;C;6.00;;7,0;100;0.00;00000000\r"
    relay.add(Fault.replace("JPOSF", pose))
    with robot_on(relay) as robot:
        with pytest.raises(RepliesOutOfStep, match="does not fit the request 'JPOSF'"):
            robot.joints()
        assert robot.joints().values("J1") == (0.0,)


def test_a_lost_save_answer_is_outcome_unknown_then_reports_what_is_held(relay) -> None:  # type: ignore[no-untyped-def]
    relay.add(Fault.drop("SAVE"))
    with robot_on(relay, SILENT_S) as robot, pytest.raises(SaveOutcomeUnknown) as lost:
        robot.load_project(project(PROGRAM, POINTS))
    message = str(lost.value)
    assert isinstance(lost.value, SavedNotConfirmed)
    assert "saved, but not confirmed" in message and "was lost" in message
    assert "as many steps and positions as were sent" in message and "probably saved" in message
    assert lost.value.held is not None and lost.value.held.lines == 41
    assert held_program(relay) is not None and len(held_program(relay) or []) == 41


def test_the_last_emdat_refused_after_a_shift_saves_nothing(relay) -> None:  # type: ignore[no-untyped-def]
    old = with_old_program(relay)
    # One stray reply before the first EMDAT's shifts every later pair by one; the last
    # EMDAT is refused (a syntax error on the last line), and that refusal now arrives as
    # the answer to the request after it.
    relay.add(Fault.extra_before("EMDAT", b"QoK\r"))
    broken = PROGRAM.replace("420 END", "420 MOV (")
    with robot_on(relay) as robot, pytest.raises((RobotError, RepliesOutOfStep)) as failed:
        robot.load_project(project(broken, POINTS))
    assert "out of step" in str(failed.value)
    assert "SAVE" not in relay.commands()
    assert held_program(relay) == old


def _upload(relay: FaultRelay) -> object:
    with robot_on(relay, SILENT_S) as robot:
        return robot.load_project(project(PROGRAM, POINTS))


def test_a_link_drop_at_every_step_of_an_upload_never_saves_a_truncated_program() -> None:
    clean = FaultRelay()
    try:
        with_old_program(clean)
        _upload(clean)
        steps = list(clean.lines)
    finally:
        clean.close()
    assert any("SAVE" in line for line in steps) and len(steps) > 10
    save_at = next(i for i, line in enumerate(steps) if line.endswith(";SAVE"))
    for index, line in enumerate(steps):
        command = line.split(";", 2)[-1]
        nth = sum(1 for earlier in steps[: index + 1] if command[:8] in earlier)
        for after in (False, True):
            relay = FaultRelay()
            try:
                old = with_old_program(relay)
                relay.add(Fault.hang_up(command[:8], nth, after=after))
                error: BaseException | None = None
                try:
                    _upload(relay)
                except (LinkError, SaveOutcomeUnknown) as exc:
                    error = exc
                # Only a drop while the session closes (CLOSE) may go unnoticed.
                assert error is not None or command == "CLOSE", (command, after)
                held = held_program(relay)
                assert held in (old, _sent_steps()), (command, after, held)
                saved = held == _sent_steps()
                assert saved == (index > save_at or (index == save_at and after)), (command, after)
                if command == "SAVE":  # sent, answer lost: the client cannot know which
                    assert "outcome unknown" in str(error)
            finally:
                relay.close()


def _sent_steps() -> list[str]:
    return [f"{10 * i} MOV P{1 + i % 3}" for i in range(1, 41)] + ["420 END"]


def test_stop_succeeds_while_an_earlier_request_is_never_answered(relay) -> None:  # type: ignore[no-untyped-def]
    relay.add(Fault.drop("JPOSF"))
    with robot_on(relay, 3.0) as robot:
        robot.connect()
        errors: list[BaseException] = []

        def read() -> None:
            try:
                robot.joints()
            except BaseException as exc:
                errors.append(exc)

        worker = threading.Thread(target=read)
        worker.start()
        while not any("JPOSF" in line for line in relay.lines):
            threading.Event().wait(0.01)
        robot.stop()  # accepted although JPOSF is never answered
        worker.join(10)
        assert not worker.is_alive()
        assert errors and isinstance(errors[0], LinkTimeout)
        assert relay.commands()[-1] == "STOP"
        assert robot.state().program == ""  # the session carries on after resynchronising


def test_cli_exit_codes_for_faults(relay) -> None:  # type: ignore[no-untyped-def]
    relay.add(Fault.replace("JPOSF", b"QoK\r"))
    runner = CliRunner()
    result = runner.invoke(app, ["pose", "--robot", relay.new_port(), "--timeout", "1"])
    assert result.exit_code == 3, result.output
    assert "out of step" in result.output and "Traceback" not in result.output
