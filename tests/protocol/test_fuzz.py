"""Any bytes from the controller give replies or RemoteProtocolError, nothing else."""

import contextlib

from hypothesis import given
from hypothesis import strategies as st

from melfa.protocol import (
    DState,
    ErrorStatus,
    Jog,
    OpenBanner,
    Position,
    RemoteProtocolError,
    ReplyReader,
    RequestReader,
    State,
)

near_valid = st.lists(
    st.sampled_from(
        [b"Q", b"o", b"K", b"e", b"R", b"r", b"k", b"\r", b"\n", b";", b"1", b"*", b"J1"]
    )
    | st.binary(max_size=4),
    max_size=60,
).map(b"".join)
answers = st.lists(
    st.sampled_from(["", ";", ",", "*", "J1", "X", "7", "-1.5", "A1", "0", "F", "\r", "nan"]),
    max_size=30,
).map("".join)


@given(st.lists(st.binary(max_size=40) | near_valid, max_size=10))
def test_reply_reader_only_raises_remote_errors(pieces: list[bytes]) -> None:
    reader = ReplyReader(max_size=64)
    for piece in pieces:
        reader.feed(piece)
        while True:
            try:
                if reader.next_reply() is None:
                    break
            except RemoteProtocolError:
                continue
    with contextlib.suppress(RemoteProtocolError):
        reader.feed_eof()


@given(st.lists(st.binary(max_size=300), max_size=5))
def test_request_reader_only_raises_remote_errors(pieces: list[bytes]) -> None:
    reader = RequestReader(max_size=400)
    for piece in pieces:
        reader.feed(piece)
        while True:
            try:
                if reader.next_request() is None:
                    break
            except RemoteProtocolError as exc:
                assert exc.error_number in (6010, 6080)


@given(st.text(max_size=120) | answers)
def test_answer_parsers_only_raise_remote_errors(text: str) -> None:
    for parse in (
        Position.parse,
        State.parse,
        DState.parse,
        OpenBanner.parse,
        ErrorStatus.parse,
        Jog.parse,
    ):
        with contextlib.suppress(RemoteProtocolError):
            parse(text)
