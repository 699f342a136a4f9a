"""Every reply a real controller sent (tests/fixtures/real_traffic.py) is read to the right
meaning: nothing real is "garbled", refusals keep their detail digits, ``****`` is a known
state, and each answer type reads its real layout."""

from __future__ import annotations

import re

import pytest

from melfa.protocol import (
    POSITION_UNKNOWN_TEXT,
    ErrorCode,
    ErrorLogEntry,
    ModeKey,
    Ok,
    OpenBanner,
    Parameter,
    Position,
    PositionUnknown,
    ProgramEntry,
    Refused,
    Request,
    State,
    StopStatus,
    decode_reply,
    encode_reply,
    error_text,
    lookup,
    parse_request,
)
from melfa.protocol.answers import RunStatus
from melfa.protocol.commands import Evidence
from tests.fixtures.real_traffic import BANNER_K9B, PAIRS, RTTOOLBOX_SEQUENCES


def _command(request: str) -> str:
    return request.split(";", 2)[2]


@pytest.mark.parametrize(("tag", "request_text", "reply_text"), PAIRS)
def test_every_real_reply_decodes_and_round_trips(
    tag: str, request_text: str, reply_text: str
) -> None:
    reply = decode_reply(reply_text.encode("latin-1"))
    assert encode_reply(reply) == reply_text.encode("latin-1") + b"\r", tag
    assert reply.alarm == (reply_text[2] in "kr")


@pytest.mark.parametrize(("tag", "request_text", "reply_text"), PAIRS)
def test_every_real_request_is_a_request_we_can_build_and_a_command_we_know(
    tag: str, request_text: str, reply_text: str
) -> None:
    request = parse_request(request_text.encode("latin-1") + b"\r")
    assert request.to_bytes() == request_text.encode("latin-1") + b"\r"
    spec = lookup(request.command)
    assert spec is not None, request_text
    assert spec.evidence is Evidence.TRACE, f"{spec.name} is answered in {tag}"


def test_refusals_in_the_9_digit_form_keep_number_and_detail() -> None:
    replies = {r: decode_reply(b) for r, b in [(t, t.encode()) for t in ("QeR602000000",)]}
    refused = replies["QeR602000000"]
    assert refused == Refused(6020, alarm=False, detail="00000")
    alarm = decode_reply(b"Qer515000000")
    assert isinstance(alarm, Refused) and alarm.alarm and alarm.error == 5150
    assert alarm.code.wire == "515000000"
    assert decode_reply(b"QeR6020") == Refused(6020)
    assert Request(f"ERRORMES{refused.code.wire}").command == "ERRORMES602000000"


@pytest.mark.parametrize(
    ("request_text", "number"),
    [(r, int(r[len("1;1;ERRORMES") :][:4])) for _, r, _ in PAIRS if "ERRORMES" in r],
)
def test_errormes_texts_on_record_are_the_texts_in_our_table(
    request_text: str, number: int
) -> None:
    text = next(reply for _, r, reply in PAIRS if r == request_text)[3:]
    assert error_text(number).endswith(" " + text)


@pytest.mark.parametrize("reply_text", [r for _, q, r in PAIRS if "ERRORRD" in q and len(r) > 3])
def test_errorrd_log_entries(reply_text: str) -> None:
    entry = ErrorLogEntry.parse(reply_text[3:])
    assert entry is not None
    assert entry.code.number == entry.number
    assert error_text(entry.number).endswith(" " + entry.text)
    assert entry.level is not None and error_text(entry.number)[0] == entry.level.letter
    assert entry.to_answer() == reply_text[3:]
    assert ErrorLogEntry.parse("") is None


@pytest.mark.parametrize("reply_text", [r for _, q, r in PAIRS if q.endswith("STATE")])
def test_state_answers_read_mode_key_stop_bits_and_alarm(reply_text: str) -> None:
    state = State.parse(reply_text[3:])
    assert state.mode == "REP" and state.start_condition == "START"
    status = state.status
    assert status.mode is (ModeKey.TEACH if RunStatus.TEACH in status.run else ModeKey.AUTO)
    if StopStatus.TEACH_PENDANT in status.stop:
        assert status.mode is ModeKey.TEACH
    assert (status.error != 0) == (reply_text[2] == "k")
    assert state.to_answer() == reply_text[3:]


def test_state_with_alarm_4300_folded_into_the_status_field() -> None:
    status = State.parse("0;32;0;01124300;0;1;;;;;;;;;REP;START;1;0".replace("0;32", ";0;32", 1))
    assert status.status.error == 4300
    assert status.status.run == RunStatus.REPEAT
    assert status.status.stop == StopStatus.STOP | StopStatus.PROGRAM_SELECT


@pytest.mark.parametrize(
    ("request_text", "reply_text"), [(q, r) for _, q, r in PAIRS if "POSF" in q]
)
def test_position_answers_including_unknown_positions(request_text: str, reply_text: str) -> None:
    position = Position.parse(reply_text[3:])
    assert position.to_answer() == reply_text[3:]
    names = ("J1", "J2", "J3", "J4", "J5", "J6") if "JPOSF" in request_text else "XYZABC"
    if "****" in reply_text.split(";;")[0]:
        assert position.unknown
        with pytest.raises(PositionUnknown, match=re.escape(POSITION_UNKNOWN_TEXT)):
            position.values(*names)
    else:
        assert not position.unknown
        assert len(position.values(*names)) == 6


@pytest.mark.parametrize("reply_text", [r for _, q, r in PAIRS if "PDIR" in q])
def test_pdir_entries(reply_text: str) -> None:
    entry = ProgramEntry.parse(reply_text[3:])
    if entry.empty:
        assert entry.count == 0 and entry.free == 225536
        return
    assert entry.size is not None and entry.size > 0
    assert entry.lines is not None and entry.points is not None
    assert entry.fields[0].endswith(".MB4")


def test_pdir_reads_the_listing_of_the_uploaded_program() -> None:
    first = ProgramEntry.parse("KAMAL.MB4;131149;22-11-0913:55:14;2;93440;12;;2773;939;0;0;0;0")
    assert (first.name, first.count, first.free, first.lines, first.points) == (
        "KAMAL",
        2,
        93440,
        2773,
        939,
    )
    nth = ProgramEntry.parse("TESTT.MB4;548;22-11-0914:18:24;12;;8;4;0;0;0;0")
    assert (nth.name, nth.count, nth.free, nth.lines, nth.points) == ("TESTT", None, None, 8, 4)


@pytest.mark.parametrize(
    "reply_text", [r for _, q, r in PAIRS if q.startswith(("1;1;PNR", "1;1;PAR"))]
)
def test_parameter_answers(reply_text: str) -> None:
    parameter = Parameter.parse(reply_text[3:])
    assert parameter.name and parameter.values
    if parameter.count is not None and parameter.name != "RLNG":
        assert len(parameter.values) == parameter.count


def test_banners_of_both_firmwares() -> None:
    k9b = OpenBanner.parse(BANNER_K9B[3:])
    assert (k9b.robot_type, k9b.version, k9b.edit_slot) == ("RV-1A", "Ver.K9b", 9)
    cr2b = next(r for t, q, r in PAIRS if t == "K4a-CR2B" and "OPEN" in q)
    banner = OpenBanner.parse(cr2b[3:])
    assert (banner.robot_type, banner.version, banner.edit_slot) == ("RV-3SB", "Ver.K4a", 9)


def test_ok_answers_of_commands_that_answer_data() -> None:
    overrides = [decode_reply(r.encode()) for _, q, r in PAIRS if q.startswith("1;1;OVRD=")]
    assert [o.answer for o in overrides if isinstance(o, Ok)] == ["5", "25", "100"]


def test_every_command_of_the_real_clients_sequences_is_in_the_table() -> None:
    for name, sequence in RTTOOLBOX_SEQUENCES.items():
        for request in sequence:
            if not request[:1].isdigit():
                continue
            command = request.split(" -> ")[0].split(";", 2)[2].rstrip("…")
            assert lookup(command) is not None, (name, request)


def test_error_codes() -> None:
    assert ErrorCode.parse("602000000") == ErrorCode(6020, "00000")
    for bad in ("60200", "60200000", "6020000000", "x", ""):
        with pytest.raises(ValueError, match="error number"):
            ErrorCode.parse(bad)
