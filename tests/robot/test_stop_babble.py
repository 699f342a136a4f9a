"""STOP on a babbling line: once the controller answers it, `stop()` succeeds, whatever line
noise came before or after its answer; with no answer at all it is "sent, not confirmed".

A real pty at 9600 8E2; the far end is the virtual controller, with noise put around its
replies while `babble` is on (the noise a loose connector or a second device on the line
makes)."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import pytest

from melfa.link import LinkSettings, SerialLink
from melfa.robot import Robot
from melfa.robot.channel import StopNotConfirmed
from melfa.sim import VirtualController
from tests.robot.fake import FakeController
from tests.waiting import wait_until

NOISE = b"\x13\x7f%#\r"


class Babbler:
    def __init__(self) -> None:
        self.controller = VirtualController()
        self.babble = False
        self.silent = False
        self.fake = FakeController(self._answer)

    def _answer(self, line: bytes) -> bytes:
        reply = self.controller.handle(line + b"\r", time.monotonic())
        if self.silent:
            return NOISE
        return NOISE + reply + b"~~\r" if self.babble else reply


@pytest.fixture
def babbler() -> Iterator[Babbler]:
    made = Babbler()
    yield made
    made.fake.close()


def test_stop_succeeds_once_answered_whatever_the_noise_around_it(babbler: Babbler) -> None:
    with Robot(SerialLink(babbler.fake.path, LinkSettings(timeout=2))) as robot:
        robot.connect()
        babbler.babble = True
        robot.stop()
        robot.stop()  # the line is out of step now: STOP still goes out at once
        babbler.babble = False
        assert robot.joints().values("J1") == (0.0,)  # the session resynchronised
    assert babbler.fake.lines.count(b"1;1;STOP") == 2


def test_stop_with_only_noise_in_reply_is_sent_not_confirmed(babbler: Babbler) -> None:
    with Robot(SerialLink(babbler.fake.path, LinkSettings(timeout=0.5))) as robot:
        robot.connect()
        babbler.silent = True
        with pytest.raises(StopNotConfirmed, match="sent"):
            robot.stop()
    assert b"1;1;STOP" in babbler.fake.lines


def test_a_lost_stop_answer_is_not_confirmed_by_an_earlier_requests_reply() -> None:
    controller = VirtualController()

    def answer(line: bytes) -> bytes:
        if line.endswith(b"JPOSF"):
            time.sleep(0.3)  # STOP goes out while JPOSF awaits its reply
        reply = controller.handle(line + b"\r", time.monotonic())
        return b"" if line.endswith(b"STOP") else reply  # STOP's answer is lost

    fake = FakeController(answer)
    try:
        with Robot(SerialLink(fake.path, LinkSettings(timeout=1))) as robot:
            robot.connect()
            joints: list[object] = []
            reader = threading.Thread(target=lambda: joints.append(robot.joints()))
            reader.start()
            wait_until(lambda: fake.lines and fake.lines[-1].endswith(b"JPOSF"), 5, what="JPOSF")
            with pytest.raises(StopNotConfirmed):
                robot.stop()
            reader.join(5)
            assert joints, "the JPOSF reply still reached its own request"
    finally:
        fake.close()
