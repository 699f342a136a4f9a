import pytest

from melfa.protocol import (
    MAX_COMMAND_BYTES,
    REQUEST_LIMIT,
    EditRefused,
    LocalProtocolError,
    Ok,
    Refused,
    RemoteProtocolError,
    Request,
    decode_reply,
    encode_reply,
    parse_request,
)
from tests.protocol.cases import REPLIES, REQUESTS


@pytest.mark.parametrize(("request_", "wire"), REQUESTS)
def test_request_writes_exact_bytes(request_: Request, wire: bytes) -> None:
    assert request_.to_bytes() == wire


@pytest.mark.parametrize(("request_", "wire"), REQUESTS)
def test_parse_request_reads_back(request_: Request, wire: bytes) -> None:
    assert parse_request(wire) == request_


@pytest.mark.parametrize(("reply", "wire"), REPLIES)
def test_encode_reply_exact_bytes(reply: Ok | Refused | EditRefused, wire: bytes) -> None:
    assert encode_reply(reply) == wire


@pytest.mark.parametrize(("reply", "wire"), REPLIES)
def test_decode_reply_reads_back(reply: Ok | Refused | EditRefused, wire: bytes) -> None:
    assert decode_reply(wire[:-1]) == reply


def test_crlf_terminator_for_cterm232_1() -> None:
    assert encode_reply(Ok("1"), terminator=b"\r\n") == b"QoK1\r\n"


def test_four_reply_cases_are_distinct() -> None:
    forms = {decode_reply(w) for w in (b"QoK1", b"Qok1", b"QeR0001", b"Qer0001")}
    assert forms == {Ok("1"), Ok("1", alarm=True), Refused(1), Refused(1, alarm=True)}


def test_request_limit_is_checked_when_built() -> None:
    room = REQUEST_LIMIT - len("1;9;")
    assert len(Request("X" * room, slot=9).to_bytes()) == REQUEST_LIMIT + 1
    with pytest.raises(LocalProtocolError, match=f"limit is {REQUEST_LIMIT}"):
        Request("X" * (room + 1), slot=9)
    assert REQUEST_LIMIT <= MAX_COMMAND_BYTES


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"command": ""}, "empty"),
        ({"command": "EXECMOV P1\rSTOP"}, "column 11"),
        ({"command": "EXEC'é"}, "non-ASCII"),
        ({"command": "STOP", "robot": 4}, "robot number 4"),
        ({"command": "STOP", "slot": 34}, "slot number 34"),
    ],
)
def test_bad_requests_say_what(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(LocalProtocolError, match=match):
        Request(**kwargs)  # type: ignore[arg-type]


def test_parse_request_defaults_and_errors() -> None:
    assert parse_request(b"STATE") == Request("STATE")
    assert parse_request(b";;SRVON\r\n") == Request("SRVON")
    with pytest.raises(RemoteProtocolError) as too_long:
        parse_request(b"1;9;EMDAT" + b"x" * 300)
    assert too_long.value.error_number == 6080
    with pytest.raises(RemoteProtocolError) as bad_slot:
        parse_request(b"1;99;STOP")
    assert bad_slot.value.error_number == 6010
    with pytest.raises(RemoteProtocolError) as binary:
        parse_request(b"1;1;\xffSTOP")
    assert binary.value.error_number == 6010


def test_request_name() -> None:
    assert Request("EXECMOV P1").name == "EXECMOV"
    assert Request("RUN1;1").name == "RUN"
    assert Request("1;2").name == ""


@pytest.mark.parametrize(
    "line", [b"", b"QOK", b"Hello", b"QeR", b"QeRabc", b"QeR12345", b"Qer1;2;3;4", b"QoK\x00"]
)
def test_decode_garbage_is_remote_error(line: bytes) -> None:
    with pytest.raises(RemoteProtocolError):
        decode_reply(line)


def test_reply_values_are_checked() -> None:
    with pytest.raises(LocalProtocolError):
        Ok("a\rb")
    with pytest.raises(LocalProtocolError):
        Refused(10000)
    with pytest.raises(LocalProtocolError):
        EditRefused(4220, -1, 0)
