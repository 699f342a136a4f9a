"""The client's turn-taking rules as a small state machine: pairing that cannot shift silently.

One request, one reply, strictly in turn [DOC S1 §1]; the controller answers in order. The
only exception is ``STOP``: it must never wait behind a slow reply, so it may be sent while
requests are outstanding. Replies are matched first-in, first-out, and every reply is
checked to *fit* its request (`melfa.protocol.commands.fits`: an empty ``QoK`` to NEW/EMDAT/
SAVE, ``J1;…`` to JPOSF, ``RLNG;…`` to PARRLNG…). A reply that does not fit, a reply with
no request, an unreadable reply or an abandoned request (timeout) loses the pairing: the
connection is BROKEN, and nothing but STOP is sent until it has been *resynchronised* with a
request whose answer names itself (``PARRLNG`` → ``QoKRLNG;…``): every reply before that
answer is dropped as late or stray, so a late reply can never be taken for a later
request's.

State table::

    IDLE            --send(r)-->            AWAITING_REPLY
    AWAITING_REPLY  --send(STOP)-->         AWAITING_REPLY   (one more outstanding)
    AWAITING_REPLY  --send(other)-->        LocalProtocolError (unless within a window)
    AWAITING_REPLY  --last fitting reply--> IDLE
    any             --garbage/unfit/unsolicited/abandon--> BROKEN
    BROKEN          --begin_resync()-->     RESYNCING  (PARRLNG sent)
    RESYNCING       --QoKRLNG;…-->          IDLE      (`Resynced` with what was dropped)

>>> c = ClientConnection()
>>> c.send(Request("JPOSF"))
b'1;1;JPOSF\\r'
>>> c.send(Request("STOP"))  # overtakes
b'1;1;STOP\\r'
>>> c.receive_data(b"QoKJ1;0.00;;****,****;100;0.00;00000000\\rQoK\\r")
>>> c.next_event().request.command, c.next_event().request.command, c.state.name
('JPOSF', 'STOP', 'IDLE')
"""

from __future__ import annotations

import enum
from collections import deque
from dataclasses import dataclass

from melfa.protocol.commands import OVERTAKING_COMMANDS, RESYNC_COMMAND, fits
from melfa.protocol.errors import LocalProtocolError, RemoteProtocolError
from melfa.protocol.messages import Ok, Reply, Request
from melfa.protocol.reader import MAX_REPLY_BYTES, ReplyReader

MAX_DROPPED = 32
"""Replies dropped while resynchronising before we give up on the line."""


class ClientState(enum.Enum):
    """Where the conversation stands."""

    IDLE = "idle"
    AWAITING_REPLY = "awaiting reply"
    BROKEN = "broken"
    RESYNCING = "resynchronising"


@dataclass(frozen=True)
class Paired:
    """``reply`` answers ``request``."""

    request: Request
    reply: Reply


@dataclass(frozen=True)
class Unanswered:
    """``request`` will get no reply of its own: the reply that arrived in its turn fits
    the STOP sent after it, not it (the controller answered the STOP and dropped it)."""

    request: Request
    reason: str


@dataclass(frozen=True)
class Resynced:
    """The resynchronising request was answered: pairing is sound again. ``dropped`` are the
    replies thrown away before its answer (late or stray); ``orphans`` the requests that
    were outstanding meanwhile (a STOP sent while broken), whose replies are among them."""

    dropped: tuple[Reply, ...]
    orphans: tuple[Request, ...]


Event = Paired | Unanswered | Resynced


class ClientConnection:
    """Pairs replies with requests, checks that each fits, refuses out-of-turn sends. No I/O."""

    def __init__(
        self, max_reply_size: int = MAX_REPLY_BYTES, resync_command: str = RESYNC_COMMAND
    ) -> None:
        self._reader = ReplyReader(max_reply_size)
        self._outstanding: deque[Request] = deque()
        self._broken: str | None = None
        self._fence: Request | None = None
        self._fence_command = resync_command
        self._dropped: list[Reply] = []
        self._ready: deque[Event] = deque()
        self._unchecked: list[Request] = []

    @property
    def state(self) -> ClientState:
        """Current state."""
        if self._fence is not None:
            return ClientState.RESYNCING
        if self._broken is not None:
            return ClientState.BROKEN
        return ClientState.AWAITING_REPLY if self._outstanding else ClientState.IDLE

    @property
    def broken_reason(self) -> str | None:
        """Why the pairing was lost (None while it is sound)."""
        return self._broken

    @property
    def has_events(self) -> bool:
        """Events are ready for `next_event` (a STOP paired while the pairing broke)."""
        return bool(self._ready)

    @property
    def outstanding(self) -> tuple[Request, ...]:
        """Requests sent and not yet answered, oldest first."""
        return tuple(self._outstanding)

    def send(self, request: Request, *, window: int = 1, check_fit: bool = True) -> bytes:
        """Register ``request`` as sent and return its bytes.

        ``window`` > 1 allows that many requests in flight (opt-in pipelining of a batch such
        as EMDAT chunks). STOP is always allowed through, even while broken. Without
        ``check_fit`` the reply in its turn is taken whatever its shape (a probe of what the
        controller answers, as ``melfa doctor`` sends; its caller reads it tolerantly).
        """
        overtaking = request.name in OVERTAKING_COMMANDS
        if not overtaking:
            if self._fence is not None or self._broken is not None:
                raise LocalProtocolError(
                    f"replies are out of step ({self._broken}); resynchronise first"
                )
            waiting = [r for r in self._outstanding if r.name not in OVERTAKING_COMMANDS]
            if len(waiting) >= max(window, 1):
                raise LocalProtocolError(
                    f"cannot send {request.name or request.command!r} while "
                    f"{waiting[0].name!r} awaits its reply"
                )
        self._outstanding.append(request)
        if not check_fit:
            self._unchecked.append(request)
        return request.to_bytes()

    def begin_resync(self, robot: int = 1) -> bytes:
        """From BROKEN: the bytes of the resynchronising request (``1;1;PARRLNG``)."""
        if self._broken is None:
            raise LocalProtocolError("the pairing is sound; nothing to resynchronise")
        self._reader.clear()
        self._dropped = []
        self._fence = Request(self._fence_command, robot=robot)
        return self._fence.to_bytes()

    def receive_data(self, data: bytes) -> None:
        """Hand over received bytes."""
        self._reader.feed(data)

    @property
    def pending(self) -> int:
        """Received bytes not yet making a whole reply."""
        return self._reader.pending

    def next_event(self) -> Event | None:
        """The next pairing event, or None if more data is needed.

        Raises `RemoteProtocolError` (and the connection is BROKEN) for an unreadable reply,
        a reply with no request, or a reply that does not fit its request.
        """
        if self._ready:
            return self._ready.popleft()
        if self._broken is not None and self._fence is None:
            raise LocalProtocolError(f"replies are out of step ({self._broken}); resynchronise")
        while self._fence is not None:  # drop everything before the fence's answer
            try:
                dropping = self._reader.next_reply()
            except RemoteProtocolError:
                self._dropped.append(Ok("<unreadable>"))
                self._check_dropped()
                continue
            if dropping is None:
                return None
            event = self._resync_step(dropping)
            if event is not None:
                return event
        try:
            reply = self._reader.next_reply()
        except RemoteProtocolError as exc:
            self._break(f"unreadable reply ({exc})")
            raise
        if reply is None:
            return None
        if not self._outstanding:
            self._break("a reply came with no request")
            raise RemoteProtocolError(f"unsolicited reply {_show(reply)}: replies are out of step")
        head = self._outstanding[0]
        unchecked = any(r is head for r in self._unchecked)
        if unchecked or fits(head, reply):
            self._outstanding.popleft()
            self._forget(head)
            return Paired(head, reply)
        stops = [r for r in list(self._outstanding)[1:] if r.name in OVERTAKING_COMMANDS]
        if stops and fits(stops[0], reply):
            self._outstanding.popleft()
            self._forget(head)
            self._outstanding.remove(stops[0])
            self._break(f"{head.name} got no reply of its own")
            self._ready.append(Paired(stops[0], reply))
            return Unanswered(head, f"no reply to {head.command[:40]!r}; the STOP was answered")
        self._break(f"reply {_show(reply)} does not fit {head.command[:40]!r}")
        raise RemoteProtocolError(
            f"the reply {_show(reply)} does not fit the request {head.command[:40]!r}: "
            "replies are out of step"
        )

    def _resync_step(self, reply: Reply) -> Event | None:
        assert self._fence is not None
        if isinstance(reply, Ok) and fits(self._fence, reply):
            dropped, orphans = tuple(self._dropped), tuple(self._outstanding)
            self._fence = None
            self._broken = None
            self._dropped = []
            self._outstanding.clear()
            self._unchecked.clear()
            return Resynced(dropped, orphans)
        self._dropped.append(reply)
        self._check_dropped()
        return None

    def replies_while_broken(self) -> list[Reply]:
        """While BROKEN: the readable replies received so far, taken out of the buffer
        (unreadable ones skipped); pairing stays lost. Where an overtaking STOP finds its
        answer after line noise: any ``QoK`` that came after it went out."""
        replies: list[Reply] = []
        while True:
            try:
                reply = self._reader.next_reply()
            except RemoteProtocolError:
                continue
            if reply is None:
                return replies
            replies.append(reply)

    def _forget(self, request: Request) -> None:
        self._unchecked = [r for r in self._unchecked if r is not request]

    def _check_dropped(self) -> None:
        if len(self._dropped) > MAX_DROPPED:
            self._fence = None
            raise RemoteProtocolError(
                f"{len(self._dropped)} replies without the resynchronising answer: "
                "the line is not carrying this controller's replies"
            )
        return

    def _break(self, reason: str) -> None:
        self._broken = reason

    def abandon(self, reason: str) -> None:
        """Give up on the outstanding replies (timeout, cancel): pairing is lost."""
        if self._outstanding or self._reader.pending or self._fence is not None:
            self._broken = reason
            self._fence = None
            self._outstanding.clear()
            self._unchecked.clear()

    def mark_broken(self, reason: str) -> None:
        """Declare the pairing lost (stray bytes seen while idle, a lost reply)."""
        self._broken = reason
        self._outstanding.clear()
        self._unchecked.clear()

    def reset(self) -> None:
        """Start afresh on a fresh line (a new session after reconnecting)."""
        self._reader.clear()
        self._outstanding.clear()
        self._unchecked.clear()
        self._broken = None
        self._fence = None
        self._dropped = []
        self._ready.clear()


def _show(reply: Reply) -> str:
    text = repr(reply)
    return text if len(text) <= 60 else text[:59] + "…"
