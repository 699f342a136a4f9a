"""Split-input tests (h11 style): whole, byte by byte, and with junk after."""

from collections.abc import Iterator

import pytest

from melfa.protocol import (
    LineSplitter,
    Ok,
    Refused,
    RemoteProtocolError,
    Reply,
    ReplyReader,
    Request,
    RequestReader,
)
from tests.protocol.cases import REPLIES, REQUESTS


def pieces(data: bytes, mode: str) -> Iterator[bytes]:
    if mode == "whole":
        yield data
    elif mode == "bytes":
        for i in range(len(data)):
            yield data[i : i + 1]
    else:  # halves
        yield data[: len(data) // 2]
        yield data[len(data) // 2 :]


def read_all(data: bytes, mode: str) -> list[Reply]:
    reader = ReplyReader()
    out: list[Reply] = []
    for piece in pieces(data, mode):
        reader.feed(piece)
        out.extend(reader)
    return out


MODES = ["whole", "bytes", "halves"]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("reply", "wire"), REPLIES)
def test_each_reply_in_pieces(reply: Reply, wire: bytes, mode: str) -> None:
    assert read_all(wire, mode) == [reply]


@pytest.mark.parametrize("mode", MODES)
def test_all_replies_back_to_back_with_crlf(mode: str) -> None:
    stream = b"".join(w[:-1] + b"\r\n" for _, w in REPLIES)
    assert read_all(stream, mode) == [r for r, _ in REPLIES]


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize(("reply", "wire"), REPLIES)
def test_junk_after_is_held_not_decoded(reply: Reply, wire: bytes, mode: str) -> None:
    reader = ReplyReader()
    got: list[Reply] = []
    for piece in pieces(wire + b"QoKpart", mode):
        reader.feed(piece)
        got.extend(reader)
    assert got == [reply]
    assert reader.pending == len(b"QoKpart")
    with pytest.raises(RemoteProtocolError, match="middle of a reply"):
        reader.feed_eof()


def test_lf_arriving_in_the_next_read_is_dropped() -> None:
    reader = ReplyReader()
    reader.feed(b"QoK1\r")
    assert reader.next_reply() == Ok("1")
    reader.feed(b"\nQeR6010\r")
    assert reader.next_reply() == Refused(6010)


def test_unterminated_reply_is_bounded() -> None:
    reader = ReplyReader(max_size=64)
    reader.feed(b"QoK" + b"9" * 64)
    with pytest.raises(RemoteProtocolError, match="no CR within 67 bytes"):
        reader.next_reply()
    # the rest of the runaway line is skipped, then reading resumes
    reader.feed(b"99999\rQoK2\r")
    assert list(reader) == [Ok("2")]


def test_garbage_line_then_good_line() -> None:
    reader = ReplyReader()
    reader.feed(b"\x00\xfe garbage\rQoK\r")
    with pytest.raises(RemoteProtocolError):
        reader.next_reply()
    assert reader.next_reply() == Ok()


def test_empty_reply_line_is_an_error() -> None:
    reader = ReplyReader()
    reader.feed(b"\r")
    with pytest.raises(RemoteProtocolError, match="empty"):
        reader.next_reply()


def test_line_splitter_never_loses_bytes() -> None:
    splitter = LineSplitter()
    splitter.feed(b"a\r\nb\rc")
    assert [splitter.next_line(), splitter.next_line(), splitter.next_line()] == [b"a", b"b", None]
    assert splitter.pending == 1


@pytest.mark.parametrize("mode", MODES)
def test_request_reader_in_pieces(mode: str) -> None:
    stream = b"\r\n".join(w[:-1] for _, w in REQUESTS) + b"\r\n"
    reader = RequestReader()
    got: list[Request] = []
    for piece in pieces(stream, mode):
        reader.feed(piece)
        got.extend(reader)
    assert got == [r for r, _ in REQUESTS]


def test_request_reader_overlong_gives_6080() -> None:
    reader = RequestReader(max_size=300)
    reader.feed(b"1;9;EMDAT" + b"x" * 400)
    with pytest.raises(RemoteProtocolError) as exc:
        reader.next_request()
    assert exc.value.error_number == 6080
