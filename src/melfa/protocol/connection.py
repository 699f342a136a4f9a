"""The client's turn-taking rules as a small state machine (h11's ``_state.py``, shrunk).

One request, one reply, strictly in turn [DOC S1 §1]. The only exception is ``STOP``: a stop
must never wait behind a slow reply, so it may be sent while one request is outstanding. The
controller buffers its serial input and answers in order, so replies are matched to requests
first-in, first-out [GUESS: the controller queues a request that arrives while it is still
answering the previous one; bborrell's fire-and-forget JOG relies on the same]. After a
garbled reply or an abandoned request the pairing is lost: the connection is BROKEN until the
caller has drained the line and calls `reset`.

State table::

    IDLE            --send(r)-->          AWAITING_REPLY
    AWAITING_REPLY  --send(STOP)-->       AWAITING_REPLY   (one more outstanding)
    AWAITING_REPLY  --send(other)-->      LocalProtocolError (unless within a pipelining window)
    AWAITING_REPLY  --last reply-->       IDLE
    any             --garbage/abandon-->  BROKEN
    BROKEN          --reset()-->          IDLE

>>> c = ClientConnection()
>>> c.send(Request("JPOSF"))
b'1;1;JPOSF\\r'
>>> c.send(Request("STOP"))  # overtakes
b'1;1;STOP\\r'
>>> c.receive_data(b"QoKJ1;0.00;;****,****;100;0.00;00000000\\rQoK\\r")
>>> c.next_reply()[0].command, c.next_reply()[0].command, c.state.name
('JPOSF', 'STOP', 'IDLE')
"""

from __future__ import annotations

import enum
from collections import deque

from melfa.protocol.commands import OVERTAKING_COMMANDS
from melfa.protocol.errors import LocalProtocolError, RemoteProtocolError
from melfa.protocol.messages import Reply, Request
from melfa.protocol.reader import MAX_REPLY_BYTES, ReplyReader


class ClientState(enum.Enum):
    """Where the conversation stands."""

    IDLE = "idle"
    AWAITING_REPLY = "awaiting reply"
    BROKEN = "broken"


class ClientConnection:
    """Pairs replies with requests and refuses out-of-turn sends. No I/O."""

    def __init__(self, max_reply_size: int = MAX_REPLY_BYTES) -> None:
        self._reader = ReplyReader(max_reply_size)
        self._outstanding: deque[Request] = deque()
        self._broken: str | None = None

    @property
    def state(self) -> ClientState:
        """Current state."""
        if self._broken is not None:
            return ClientState.BROKEN
        return ClientState.AWAITING_REPLY if self._outstanding else ClientState.IDLE

    @property
    def outstanding(self) -> tuple[Request, ...]:
        """Requests sent and not yet answered, oldest first."""
        return tuple(self._outstanding)

    def send(self, request: Request, *, window: int = 1) -> bytes:
        """Register ``request`` as sent and return its bytes.

        ``window`` > 1 allows that many requests in flight (opt-in pipelining of a batch such
        as EMDAT chunks; [GUESS] the controller buffers them, see `PIPELINE` in the robot
        settings). STOP is always allowed through.
        """
        if self._broken is not None:
            raise LocalProtocolError(f"connection is broken ({self._broken}); reset it first")
        if len(self._outstanding) >= max(window, 1) and request.name not in OVERTAKING_COMMANDS:
            raise LocalProtocolError(
                f"cannot send {request.name or request.command!r} while "
                f"{self._outstanding[0].name!r} awaits its reply"
            )
        self._outstanding.append(request)
        return request.to_bytes()

    def receive_data(self, data: bytes) -> None:
        """Hand over received bytes."""
        self._reader.feed(data)

    def next_reply(self) -> tuple[Request, Reply] | None:
        """The oldest outstanding request with its reply, or None if more data is needed."""
        if self._broken is not None:
            raise LocalProtocolError(f"connection is broken ({self._broken}); reset it first")
        try:
            reply = self._reader.next_reply()
        except RemoteProtocolError as exc:
            self._broken = str(exc)
            raise
        if reply is None:
            return None
        if not self._outstanding:
            self._broken = "reply without a request"
            raise RemoteProtocolError(f"unsolicited reply {reply!r}")
        return self._outstanding.popleft(), reply

    def abandon(self, reason: str) -> None:
        """Give up on the outstanding replies (timeout, cancel): pairing is lost."""
        if self._outstanding or self._reader.pending:
            self._broken = reason

    def reset(self) -> None:
        """Start afresh after the caller has drained the line."""
        self._reader.clear()
        self._outstanding.clear()
        self._broken = None
