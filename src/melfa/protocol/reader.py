"""Cut a byte stream into lines at CR, bounded, for both directions.

Bytes from a serial port arrive in arbitrary pieces. A `ReplyReader` takes them as they come
and hands out one decoded reply per CR; an LF right after a CR is dropped, so both CTERM232
settings (CR, CR LF) read the same [DOC S5; protocol.md §1.1]. A line that never ends becomes
a `RemoteProtocolError` once it exceeds ``max_size`` bytes (h11's bounded receive buffer).

>>> reader = ReplyReader()
>>> reader.feed(b"QoK1;2\\r\\nQe")
>>> reader.next_reply()
Ok(answer='1;2', alarm=False)
>>> reader.next_reply() is None  # need more data
True
>>> reader.feed(b"R6020\\r")
>>> list(reader)
[Refused(error=6020, alarm=False, detail=None)]
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Final

from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.messages import Reply, Request, decode_reply, parse_request

MAX_REPLY_BYTES: Final = 2048
"""Longest reply line we hold before calling it garbage. The longest real replies (OPEN
banner, LISTL with a full 255-byte batch, STATE) are well under 512 bytes."""


class LineSplitter:
    """Split bytes at CR, drop one LF after a CR, refuse lines longer than ``max_size``.

    After an over-long line the splitter discards input up to the next CR, so one runaway
    reply costs one error, not a stream of them.
    """

    def __init__(self, max_size: int = MAX_REPLY_BYTES) -> None:
        self.max_size = max_size
        self._buffer = bytearray()
        self._after_cr = False
        self._discarding = False

    @property
    def pending(self) -> int:
        """Bytes held that do not yet form a line."""
        return len(self._buffer)

    def feed(self, data: bytes) -> None:
        """Append received bytes (may be empty)."""
        self._buffer += data

    def next_line(self) -> bytes | None:
        """The next complete line without its terminator, or None if none is complete yet."""
        while True:
            if self._after_cr and self._buffer[:1] == b"\n":
                del self._buffer[:1]
            if self._buffer:
                self._after_cr = False
            end = self._buffer.find(b"\r")
            if end < 0:
                if self._discarding:
                    self._buffer.clear()
                elif len(self._buffer) > self.max_size:
                    size = len(self._buffer)
                    self._buffer.clear()
                    self._discarding = True
                    raise RemoteProtocolError(
                        f"no CR within {size} bytes (limit {self.max_size}): "
                        "the peer is not speaking the R-protocol, or the line settings differ"
                    )
                return None
            line = bytes(self._buffer[:end])
            del self._buffer[: end + 1]
            self._after_cr = True
            if self._discarding:
                self._discarding = False
                continue
            if len(line) > self.max_size:
                raise RemoteProtocolError(f"line of {len(line)} bytes exceeds {self.max_size}")
            return line

    def take_pending(self) -> bytes:
        """Hand over the bytes held without a terminator (a peer that sends none)."""
        if self._discarding or len(self._buffer) > self.max_size:
            self.clear()
            return b""
        data = bytes(self._buffer)
        self._buffer.clear()
        return data

    def clear(self) -> None:
        """Forget everything held (after a resynchronisation)."""
        self._buffer.clear()
        self._after_cr = False
        self._discarding = False


class ReplyReader:
    """Client side: bytes in, `Reply` values out. Raises only `RemoteProtocolError`."""

    def __init__(self, max_size: int = MAX_REPLY_BYTES) -> None:
        self._lines = LineSplitter(max_size)

    @property
    def pending(self) -> int:
        """Bytes held that do not yet form a reply."""
        return self._lines.pending

    def feed(self, data: bytes) -> None:
        """Append received bytes."""
        self._lines.feed(data)

    def next_reply(self) -> Reply | None:
        """The next reply, or None when more data is needed."""
        line = self._lines.next_line()
        if line is None:
            return None
        if not line:
            raise RemoteProtocolError("empty reply line")
        return decode_reply(line)

    def feed_eof(self) -> None:
        """The peer is gone: a partial reply is an error, nothing held is fine."""
        if self._lines.pending:
            size = self._lines.pending
            self._lines.clear()
            raise RemoteProtocolError(f"connection closed in the middle of a reply ({size} bytes)")

    def clear(self) -> None:
        """Drop everything held."""
        self._lines.clear()

    def __iter__(self) -> Iterator[Reply]:
        while (reply := self.next_reply()) is not None:
            yield reply


class RequestReader:
    """Simulator side: bytes in, `Request` values out.

    Empty lines are skipped (a stray CR/LF from a terminal); a bad line raises
    `RemoteProtocolError` carrying the error number the controller would answer with.
    """

    def __init__(self, max_size: int = MAX_REPLY_BYTES) -> None:
        self._lines = LineSplitter(max_size)

    def feed(self, data: bytes) -> None:
        """Append received bytes."""
        self._lines.feed(data)

    def next_request(self) -> Request | None:
        """The next request, or None when more data is needed."""
        while True:
            try:
                line = self._lines.next_line()
            except RemoteProtocolError as exc:
                raise RemoteProtocolError(str(exc), error_number=6080) from None
            if line is None:
                return None
            if line.strip(b"\n"):
                return parse_request(line)

    def __iter__(self) -> Iterator[Request]:
        while (request := self.next_request()) is not None:
            yield request
