"""A misbehaving peer on a real pty: garbage, truncation, silence, hang-up, and STOP
overtaking a slow reply. These need a controller that breaks the rules, so they use the
small `FakeController` instead of the simulator (still a real pty and the real serial path)."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator

import pytest

from melfa.link import LinkClosed, LinkSettings, LinkTimeout, SerialLink
from melfa.protocol import RemoteProtocolError
from melfa.robot import ControllerError, Robot
from tests.plans import program_plan
from tests.robot.fake import OPEN_BANNER, FakeController
from tests.waiting import wait_until

REPLY_TIMEOUT_S = 10.0
"""Generous: a loaded machine must not turn a prompt reply into a timeout."""
SILENCE_TIMEOUT_S = 0.5
"""Only for tests that wait for a timeout to fire (keeps them fast)."""

JPOSF = b"QoKJ1;1.00;J2;2.00;J3;3.00;J4;4.00;J5;5.00;J6;6.00;;****,****;100;0.00;00000000\r"


@pytest.fixture
def fake_robot() -> Iterator[
    Callable[[Callable[[bytes], bytes | None]], tuple[Robot, FakeController]]
]:
    made: list[tuple[Robot, FakeController]] = []

    def make(
        script: Callable[[bytes], bytes | None], timeout: float = REPLY_TIMEOUT_S
    ) -> tuple[Robot, FakeController]:
        fake = FakeController(script)
        robot = Robot(SerialLink(fake.path, LinkSettings(timeout=timeout)))
        made.append((robot, fake))
        return robot, fake

    yield make
    for robot, fake in made:
        robot.close()
        fake.close()


def standard(line: bytes) -> bytes | None:
    if line.endswith(b"OPEN=MELFA"):
        return OPEN_BANNER
    if line.endswith(b"JPOSF"):
        return JPOSF
    if line.endswith(b"PARRLNG"):
        return b"QoKRLNG;1;1\r"
    if line.endswith(b"STATE"):
        return b"QoK;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0\r"  # real [K9b-RUN]
    return b"QoK\r"


def test_garbage_reply_is_a_clear_protocol_error_then_recovers(fake_robot) -> None:  # type: ignore[no-untyped-def]
    calls = {"n": 0}

    def script(line: bytes) -> bytes | None:
        if line.endswith(b"JPOSF"):
            calls["n"] += 1
            if calls["n"] == 1:
                return b"\x8f\x00#garbage@@\r"
        return standard(line)

    robot, _ = fake_robot(script)
    with pytest.raises(RemoteProtocolError, match="QoK/Qok/QeR/Qer"):
        robot.joints()
    assert robot.joints().values("J1") == (1.0,)


def test_truncated_reply_times_out_without_hanging(fake_robot) -> None:  # type: ignore[no-untyped-def]
    def script(line: bytes) -> bytes | None:
        if line.endswith(b"JPOSF"):
            return JPOSF[:30]  # no CR, ever
        return standard(line)

    robot, _ = fake_robot(script, SILENCE_TIMEOUT_S)
    with pytest.raises(LinkTimeout, match="JPOSF"):
        robot.joints()
    # the session carries on after draining the line
    robot.request("STATE", timeout=REPLY_TIMEOUT_S)


def test_silent_controller_times_out(fake_robot) -> None:  # type: ignore[no-untyped-def]
    robot, _ = fake_robot(
        lambda line: b"" if line.endswith(b"OPEN=MELFA") else standard(line), SILENCE_TIMEOUT_S
    )
    with pytest.raises(LinkTimeout):
        robot.connect()


def test_hang_up_mid_upload_sends_no_save(fake_robot) -> None:  # type: ignore[no-untyped-def]
    def script(line: bytes) -> bytes | None:
        if b";EMDAT" in line:
            return None  # the controller vanishes at the first EMDAT
        return standard(line)

    robot, fake = fake_robot(script)
    with pytest.raises(LinkClosed, match="unplugged"):
        robot.upload_program(program_plan("10 MOV P1\n20 END"))
    assert not any(line.endswith(b"SAVE") for line in fake.lines)


def test_refused_emdat_sends_new_not_save(fake_robot) -> None:  # type: ignore[no-untyped-def]
    def script(line: bytes) -> bytes | None:
        if b";EMDAT" in line:
            return b"QeR4220;2;3\r"
        if b"ERRORMES" in line:
            return b"QoKSyntax error\r"
        return standard(line)

    robot, fake = fake_robot(script)
    with pytest.raises(ControllerError) as exc:
        robot.upload_program(program_plan("10 MOV P1\n20 MOV\n30 END"))
    assert (exc.value.number, exc.value.line) == (4220, 2)  # type: ignore[attr-defined]
    assert exc.value.message == "L4220 Syntax error"
    sent = [line.split(b";", 2)[2] for line in fake.lines]
    assert b"SAVE" not in sent and sent[-1] == b"NEW"


def test_stop_overtakes_a_slow_reply(fake_robot) -> None:  # type: ignore[no-untyped-def]
    def script(line: bytes) -> bytes | None:
        if line.endswith(b"JPOSF"):
            return b""  # busy: answer nothing yet
        if line.endswith(b"STOP"):
            return JPOSF + b"QoK\r"  # the controller answers both, in order
        return standard(line)

    robot, fake = fake_robot(script)
    robot.connect()
    results: list[object] = []
    worker = threading.Thread(target=lambda: results.append(robot.joints()))
    worker.start()
    wait_until(lambda: fake.lines[-1:] == [b"1;1;JPOSF"])
    robot.stop()
    worker.join(30)
    assert not worker.is_alive()
    assert fake.lines[-2:] == [b"1;1;JPOSF", b"1;1;STOP"]
    assert len(results) == 1 and results[0].values("J1") == (1.0,)  # type: ignore[attr-defined]


@pytest.mark.timeout(60)  # a hang fails here, not a stopwatch
def test_stop_waits_no_longer_than_its_timeout(fake_robot) -> None:  # type: ignore[no-untyped-def]
    robot, _ = fake_robot(
        lambda line: b"" if line.endswith(b"STOP") else standard(line), SILENCE_TIMEOUT_S
    )
    robot.connect()
    with pytest.raises(LinkTimeout, match="STOP"):
        robot.stop()
