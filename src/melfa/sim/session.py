"""Bytes in, replies out: the part of every simulator server that is not I/O.

A server reads whatever bytes arrive (a request split over several reads, two requests in
one read, line noise), hands them to a `WireSession` with the time, and writes back the
replies it returns, paced by `Pacing`. Like h11's trio server example, each choice about bad
input is made here, once, for every transport:

- Lines end at CR, LF or CR LF (empty lines are ignored) [protocol.md §1.1]; bytes with no
  terminator at all are one request once the line falls quiet (`receive_idle`): the
  Robotics Library's MitsubishiR3 sends none over TCP.
- A line longer than `MAX_LINE_BYTES` without a CR is answered once with the too-long error
  and the rest up to the next CR is thrown away; the session never holds unbounded input.
- Bytes that are not a request (non-ASCII, NUL …) get the controller's answer to garbage,
  `QeR6010` (in the configured 4- or 9-digit form); nothing raises out of `receive`.
- NUL also ends a line, so RoboDK-style clients (S12, a NUL after each command) work.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.messages import encode_reply
from melfa.protocol.reader import LineSplitter
from melfa.sim.config import DEFAULT_REPLY_LATENCY_S, SECONDS_PER_CHAR_9600_8E2
from melfa.sim.controller import VirtualController

MAX_LINE_BYTES = 1024
"""Longest unterminated input held; anything over 255 bytes is refused anyway."""


@dataclass(frozen=True, slots=True)
class Answer:
    """A reply and the size of the request it answers (for pacing)."""

    reply: bytes
    request_size: int


class WireSession:
    """One connection's framing around a shared `VirtualController`.

    Thread-safe: servers may call `receive` from their own threads; the controller is
    guarded by one lock (it may be shared by a TCP and a pty server).

    >>> s = WireSession(VirtualController())
    >>> s.receive(b"1;1;OPEN=X\\r1;1;CNTL", now=0.0)[0].reply[:7]
    b'QoK3F;3'
    >>> s.receive(b"ON\\r", now=0.1)
    [Answer(reply=b'QoK\\r', request_size=11)]
    """

    def __init__(self, controller: VirtualController, lock: threading.Lock | None = None) -> None:
        self.controller = controller
        self.lock = lock or threading.Lock()
        self._lines = LineSplitter(MAX_LINE_BYTES)

    def receive(self, data: bytes, now: float) -> list[Answer]:
        """Feed received bytes; return the answers to every complete request, in order."""
        self._lines.feed(data.replace(b"\x00", b"\r").replace(b"\n", b"\r"))
        answers: list[Answer] = []
        while True:
            try:
                line = self._lines.next_line()
            except RemoteProtocolError:
                with self.lock:
                    too_long = self.controller.refuse(self.controller.config.too_long_error)
                answers.append(Answer(encode_reply(too_long), MAX_LINE_BYTES))
                continue
            if line is None:
                return answers
            if not line:
                continue
            with self.lock:
                reply = self.controller.handle(line, now)
            answers.append(Answer(reply, len(line) + 1))

    def receive_idle(self, now: float) -> list[Answer]:
        """The line fell quiet: bytes held without a terminator are one request."""
        line = self._lines.take_pending()
        if not line.strip():
            return []
        with self.lock:
            reply = self.controller.handle(line, now)
        return [Answer(reply, len(line))]

    def disconnect(self, now: float) -> None:
        """The client went away: its session ends (it must OPEN again), a jog stops."""
        with self.lock:
            self.controller.disconnect(now)
        self._lines.clear()


@dataclass(frozen=True)
class Pacing:
    """How long the line and the controller take [DERIVED protocol.md §6.1; prior-art.md §5].

    `seconds_per_char` is 12 bits / baud for 8E2 (1.25 ms at 9600). `latency` is the
    controller's processing time between the end of a request and the first reply byte
    (prior-art.md §5 measured about 100–150 ms; default 0.1 s). Servers wait for the request's
    own wire time too (its bytes reached us at pty speed), then send the reply one character
    at a time, so clients see replies arrive in pieces as they do from a real port.
    """

    seconds_per_char: float = SECONDS_PER_CHAR_9600_8E2
    latency: float = DEFAULT_REPLY_LATENCY_S

    @classmethod
    def for_baud(cls, baud: int, latency: float = DEFAULT_REPLY_LATENCY_S) -> Pacing:
        """8E2 at `baud`."""
        if baud <= 0:
            raise ValueError(f"baud rate must be positive, got {baud}")
        return cls(12 / baud, latency)

    def reply_delay(self, request_bytes: int) -> float:
        """Seconds from receiving a request to sending the first reply byte."""
        return request_bytes * self.seconds_per_char + self.latency


NO_PACING = Pacing(0.0, 0.0)
"""Replies as fast as the transport goes (tests, `--no-pacing`)."""
