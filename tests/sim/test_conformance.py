"""The virtual controller against real bytes: every recorded request, asked in the situation
it was recorded in, gets a reply of the same form as the real controller's; the recorded
RT ToolBox sessions replayed through a pty at 9600 8E2 get the recorded kinds of reply.

Form = the reply's head (QoK/Qok/QeR/Qer), and for answers the shape of every field (empty,
number, `****`, text); for refusals the error number and its 9-digit form. The data is
tests/fixtures/real_traffic.py (copied from the shared traces, sources named there). The
simulator runs strict and 9-digit, as in the rest of the suite.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import pytest
import serial

from melfa.protocol.commands import needs_rights
from melfa.sim import NO_PACING, PtyServer, SimConfig, VirtualController
from melfa.sim.config import KeySwitch
from tests.fixtures.real_traffic import PAIRS, RTTOOLBOX_SEQUENCES
from tests.fixtures_sim import Driver

LONG = "10 DLY 100\n20 END\n"
"""A program that runs long enough to be seen running and stopped."""

PROGRAMS = dict.fromkeys(("TEST", "TESTT", "SHOWOF", "PNO2", "REDUN", "KAMAL"), LONG)

_NUMBER = re.compile(r"-?[0-9A-F]*[0-9][0-9A-F]*(\.[0-9]+)?")


def _shape(field: str) -> str:
    """A field's kind; words (REP, START, ENG, axis names…) are kept as they are."""
    if not field:
        return "empty"
    if set(field) <= {"*", ","}:
        return "****"
    if _NUMBER.fullmatch(field):
        return "number"
    return field if re.fullmatch(r"[A-Z]+", field) else "text"


@dataclass(frozen=True)
class Form:
    head: str
    shapes: tuple[str, ...] = ()
    error: str = ""
    """A refusal's digits exactly (`602000000`)."""


def form(reply: str) -> Form:
    head, body = reply[:3], reply[3:]
    if head in ("QeR", "Qer"):
        return Form(head, error=body)
    return Form(head, tuple(_shape(f) for f in body.split(";")) if body else ())


def _tag_alarm(tag: str) -> int | None:
    """The alarm active while the tagged recording was made (lower-case replies)."""
    return {"K9b-C1": 5150, "K9b-C3": 4300, "K9b-C4": 5000}.get(tag)


def _situation(tag: str, request: str, reply: str) -> tuple[Driver, str]:
    """A strict 9-digit controller put where the recording was made, and the request to send
    (elided parts of the transcription filled in)."""
    command = request.split(";", 2)[2]
    refused = reply[:3] in ("QeR", "Qer")
    alarm = reply[:3] in ("Qok", "Qer")
    empty_memory = command.startswith("PDIR") and reply[3:].startswith(";")
    teach = command == "SLOTINIT" and refused
    if command == "STATE":
        teach = bool(int(reply[3:].split(";")[4][:2], 16) & 0x08)
    config = SimConfig(strict=True, origin_set=tag not in ("K9b-C1", "K9b-C4"))
    drive = Driver(VirtualController(config, programs={} if empty_memory else PROGRAMS))
    drive.ok("OPEN=TOOLBOX")
    if command == "STATE" and reply[3:].split(";")[0]:
        fields = reply[3:].split(";")
        drive.send("CNTLON")
        drive.send("SRVON")
        drive.send("PRGLOAD=TEST")
        if fields[3] in ("4", "6"):
            drive.send("RUNTEST;1")
            drive.wait(0.5)
        if fields[3] == "4":
            drive.send("STOP")
        drive.send("CNTLOFF")
    if command.startswith("RUN<name>") and refused:
        # [K9b-RAW] another program is paused in the slot: no program selection ("not PSA").
        drive.send("CNTLON")
        drive.send("SRVON")
        drive.send("RUNTEST;1")
        drive.wait(0.5)
        drive.send("STOP")
        command = command.replace("<name>", "SHOWOF")
    command = command.replace("<name>", "TEST").replace("<items>", "10 SERVO ON\x0b20 END")
    if teach:
        drive.controller.turn_key(KeySwitch.TEACH, drive.now)
    if alarm and tag == "K9b-C1":
        drive.send("CNTLON")
        drive.send("RUNTEST;1")  # origin not set: the controller raises L5150 itself
        drive.send("CNTLOFF")
    elif alarm:
        number = _tag_alarm(tag)
        assert number is not None, (tag, request)
        drive.controller.raise_alarm(number, drive.now)
    if command.startswith(("EMDAT", "EDATA")):
        drive.send("LOAD=TEST")
    if command.startswith("ERRORRD+1"):
        drive.send("ERRORRD<;0")
    if needs_rights(command) or command == "SLOTINIT":
        drive.send("CNTLON")
    return drive, command


@pytest.mark.parametrize(("tag", "request_text", "reply_text"), PAIRS)
def test_each_recorded_request_gets_a_reply_of_the_recorded_form(
    tag: str, request_text: str, reply_text: str
) -> None:
    drive, command = _situation(tag, request_text, reply_text)
    slot = int(request_text.split(";")[1])
    sent = drive.controller.handle(f"1;{slot};{command}\r".encode("latin-1"), drive.now)
    assert sent.endswith(b"\r") and b"\n" not in sent
    reply = sent[:-1].decode("latin-1")
    assert form(reply) == form(reply_text), (tag, request_text, reply, reply_text)
    if command.startswith("ERRORMES"):
        assert reply == reply_text  # the controller's own text, letter for letter
    if command.startswith("ERRORRD") and reply_text[3:]:
        # number, text, level, program, line and the 9-digit code as recorded; not the date
        assert reply.split(";")[2:] == reply_text.split(";")[2:]


def test_refusals_on_record_carry_the_recorded_numbers() -> None:
    refusals = [(t, q, r) for t, q, r in PAIRS if r[:3] in ("QeR", "Qer")]
    assert {r for _, _, r in refusals} == {"QeR602000000", "QeR512000000", "Qer515000000"}
    for tag, request, reply in refusals:
        drive, command = _situation(tag, request, reply)
        assert drive.send(command).decode() == reply + "\r"


def test_four_digit_option_answers_the_manual_form() -> None:
    drive = Driver(VirtualController(SimConfig(strict=True, nine_digit_errors=False)))
    assert drive.send("FROBNICATE") == b"QeR6010\r"
    drive.ok("OPEN=TOOLBOX")
    assert drive.send("SRVON") == b"QeR6020\r"


# ------------------------------------------------------------------ RT ToolBox sessions

FILL = {
    "1;1;EMDAT…": "1;9;EMDAT10 SERVO ON\x0b20 MOV P1\x0b30 END\x0bP1=(400,0,600,180,0,180)(7,0)",
    "1;1;EDATA 1 …": "1;1;EDATA 1 SERVO ON",
}
"""The elided requests of the transcription, filled in with real program lines."""


def _session(name: str) -> list[tuple[str, str | None]]:
    """The requests of a recorded session and the reply kind each got (None: not stated)."""
    steps: list[tuple[str, str | None]] = []
    for item in RTTOOLBOX_SEQUENCES[name]:
        if item.startswith("(") or item == "…":
            continue
        request, _, expected = item.partition(" -> ")
        steps.append((FILL.get(request, request), expected or None))
    return steps


def _recorded(request: str) -> set[Form]:
    return {form(r) for _, q, r in PAIRS if q == request and r[:3] == "QoK"}


def _read_reply(port: serial.Serial) -> bytes:
    data = b""
    while not data.endswith(b"\r"):
        chunk = port.read(1)
        assert chunk, f"no reply (got {data!r})"
        data += chunk
    return data


@pytest.mark.parametrize("name", sorted(RTTOOLBOX_SEQUENCES))
def test_recorded_rt_toolbox_sessions_replay_through_a_pty(name: str) -> None:
    teach = any(" -> QeR6020" in item for item in RTTOOLBOX_SEQUENCES[name])
    config = SimConfig(strict=True, key=KeySwitch.TEACH if teach else KeySwitch.AUTO_EXT)
    controller = VirtualController(config, programs=PROGRAMS)
    steps = _session(name)
    if steps[0][0] != "1;1;OPEN=TOOLBOX":
        controller.handle(b"1;1;OPEN=TOOLBOX\r", 0.0)
    with PtyServer(controller, pacing=NO_PACING) as server:
        port = serial.Serial(
            server.new_port(),
            9600,
            bytesize=serial.EIGHTBITS,
            parity=serial.PARITY_EVEN,
            stopbits=serial.STOPBITS_TWO,
            timeout=5,
        )
        with port:
            for request, expected in steps:
                port.write(request.encode("latin-1") + b"\r")
                reply = _read_reply(port)[:-1].decode("latin-1")
                if expected is not None:
                    assert reply == expected, (request, reply)
                    continue
                assert reply.startswith("QoK"), (request, reply)
                recorded = _recorded(request)
                if recorded:
                    assert form(reply) in recorded, (request, reply, recorded)
