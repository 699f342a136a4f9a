"""One link, many threads: requests in turn, STOP first, pairing that cannot shift.

The worker thread sends one request and waits for its reply. `Channel.stop` (any thread)
never waits behind it: STOP's bytes go out at once, after only the bytes already being
written, never behind a resynchronisation or another request's wait. Replies are paired
first-in, first-out and checked to fit their requests (`melfa.protocol.ClientConnection`).

Failure rules: a timeout, an unreadable or unfitting reply, or stray bytes seen while no
request is outstanding lose the pairing. Every outstanding request then fails with that
error, and before the next request the channel resynchronises: it sends ``PARRLNG`` and
drops every reply before ``QoKRLNG;…``, so a late reply is never taken for a later
request's. STOP's own rule: it succeeds when the controller accepted it, even if an
earlier request was never answered (the last reply after STOP went out is its answer).
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections import deque
from collections.abc import Generator, Iterable
from dataclasses import dataclass, field
from typing import Final

from melfa.link import Link, LinkError, LinkTimeout
from melfa.protocol import (
    OVERTAKING_COMMANDS,
    ClientConnection,
    ClientState,
    LocalProtocolError,
    Ok,
    RemoteProtocolError,
    Reply,
    Request,
)
from melfa.protocol.connection import Paired, Resynced, Unanswered
from melfa.protocol.messages import encode_reply

_WAIT_S: Final = 0.02


class RepliesOutOfStep(RemoteProtocolError):
    """The pairing of replies with requests was lost (a late, stray or unfitting reply)."""


class StopNotConfirmed(LinkTimeout):
    """STOP's bytes went out, but no answer confirmed it: "sent, not confirmed"."""


class StopOvertook(Exception):
    """A STOP went out since the batch began: the next request of the batch was not sent."""


@dataclass
class _Ticket:
    request: Request
    deadline: float
    after: int = 0
    ahead: int = 0
    refused_after: int = 0
    """Requests (STOP aside) still awaiting their replies when this one was sent: their
    replies come first, so they never confirm a STOP."""
    """Replies received before this request was sent."""
    reply: Reply | None = None
    error: BaseException | None = None
    done: threading.Event = field(default_factory=threading.Event)

    @property
    def is_stop(self) -> bool:
        return self.request.name in OVERTAKING_COMMANDS


class Channel:
    """Thread-safe request/reply over a `Link`."""

    def __init__(self, link: Link, robot: int = 1) -> None:
        self.link = link
        self.robot = robot
        self._conn = ClientConnection()
        self._send_lock = threading.Lock()  # normal requests, in turn (may be held long)
        self._state_lock = threading.Lock()  # pairing state + writes: held only briefly
        self._read_lock = threading.Lock()
        self._tickets: deque[_Ticket] = deque()
        self._fence: _Ticket | None = None
        self._last_reply: Reply | None = None
        self.sent_bytes = 0
        self.received_replies = 0
        self.refused_replies = 0
        """Replies read but not paired (unreadable, unfitting, unsolicited)."""
        self.resyncs = 0
        self.dropped_replies = 0
        self.stops_sent = 0
        """STOPs registered so far; a batch sent with ``stops_seen`` ends at the next one."""

    @property
    def last_reply(self) -> bytes:
        """The last reply paired with a request, as it came on the wire (for a log line
        when a reply is not understood); b"" before the first."""
        reply = self._last_reply
        return b"" if reply is None else encode_reply(reply)

    @property
    def in_step(self) -> bool:
        """False while the pairing is lost (the next request resynchronises first)."""
        return self._conn.state not in (ClientState.BROKEN, ClientState.RESYNCING)

    def request(
        self, request: Request, timeout: float | None = None, *, check_fit: bool = True
    ) -> Reply:
        """Send ``request`` and return its reply (or raise the link/protocol error).
        ``check_fit=False`` takes the reply in its turn whatever its shape (probes)."""
        if request.name in OVERTAKING_COMMANDS:
            return self.stop(request, timeout)
        with self._send_lock:
            self._settle()
            ticket = self._submit(request, timeout, check_fit=check_fit)
        return self._await(ticket)

    def stop(self, request: Request, timeout: float | None = None) -> Reply:
        """Send STOP at once and return its reply. Never takes the send lock."""
        return self._await(self._submit(request, timeout))

    def pipeline(
        self,
        requests: Iterable[Request],
        window: int,
        timeout: float | None = None,
        *,
        stops_seen: int | None = None,
    ) -> Generator[Reply, None, None]:
        """Send ``requests`` keeping up to ``window`` in flight; yield replies in order.

        If the consumer stops early (a refusal), the replies still in flight are read and
        dropped before the generator closes, so the pairing stays intact. With
        ``stops_seen`` (`stops_sent` when the batch began), no request of the batch goes
        out after a STOP: `StopOvertook` instead, checked under the lock STOP registers in.
        """
        pending: deque[_Ticket] = deque()
        source = iter(requests)
        try:
            while True:
                while len(pending) < window:
                    request = next(source, None)
                    if request is None:
                        break
                    with self._send_lock:
                        if not pending:
                            self._settle()
                        ticket = self._submit(request, timeout, window, stops_seen)
                        pending.append(ticket)
                if not pending:
                    return
                yield self._await(pending.popleft())
        finally:
            for ticket in pending:
                with contextlib.suppress(Exception):
                    self._await(ticket)

    def resync(self, timeout: float | None = None) -> None:
        """Resynchronise now if the pairing is lost (also done before the next request)."""
        with self._send_lock:
            self._settle(timeout)

    # ----------------------------------------------------------------------- plumbing

    def _settle(self, timeout: float | None = None) -> None:
        """Under the send lock: wait out STOPs in flight, resynchronise if needed, and
        look for stray bytes on a quiet line."""
        while True:
            with self._state_lock:
                oldest = self._tickets[0] if self._tickets else None
            if oldest is None:
                break
            with contextlib.suppress(Exception):  # its owner sees the error, not us
                self._await(oldest)
        if self._conn.state is ClientState.IDLE:
            self._poll_stray()
        if self._conn.state is ClientState.BROKEN:
            self._resync(timeout)

    def _poll_stray(self) -> None:
        """Bytes on a quiet line are a reply with no request: the pairing is lost. (If a
        STOP registered meanwhile, from another thread, they are its reply: pass them on.)"""
        if not self._read_lock.acquire(blocking=False):
            return
        try:
            data = self.link.read_now()
        except LinkError:  # the next write reports it
            return
        finally:
            self._read_lock.release()
        if not data:
            return
        with self._state_lock:
            self._conn.receive_data(data)
            if self._tickets:
                return
            with contextlib.suppress(RemoteProtocolError, LocalProtocolError):
                self._conn.next_event()  # a reply with no request: BROKEN
            if self._conn.state is not ClientState.BROKEN:
                self._conn.mark_broken("stray bytes on a quiet line")

    def _resync(self, timeout: float | None) -> None:
        limit = self.link.settings.timeout if timeout is None else timeout
        with self._state_lock:
            data = self._conn.begin_resync(self.robot)
            fence = _Ticket(Request("PARRLNG", robot=self.robot), time.monotonic() + limit)
            self._fence = fence
            self._write(data)
        self.resyncs += 1
        try:
            self._await(fence)
        except LinkTimeout as exc:
            raise LinkTimeout(
                f"the controller did not answer the resynchronising PARRLNG ({exc})"
            ) from None

    def _write(self, data: bytes) -> None:
        """Under the state lock."""
        try:
            self.link.write(data)
        except LinkError as exc:
            self._fail_all_locked(exc)
            raise
        self.sent_bytes += len(data)

    def _submit(
        self,
        request: Request,
        timeout: float | None,
        window: int = 1,
        stops_seen: int | None = None,
        *,
        check_fit: bool = True,
    ) -> _Ticket:
        limit = self.link.settings.timeout if timeout is None else timeout
        with self._state_lock:
            if stops_seen is not None and self.stops_sent != stops_seen:
                raise StopOvertook("a STOP was sent")
            # LocalProtocolError if out of turn
            data = self._conn.send(request, window=window, check_fit=check_fit)
            if request.name in OVERTAKING_COMMANDS:
                self.stops_sent += 1
            ahead = sum(1 for t in self._tickets if not t.is_stop)
            ticket = _Ticket(
                request,
                time.monotonic() + limit,
                self.received_replies,
                ahead,
                self.refused_replies,
            )
            self._tickets.append(ticket)
            self._write(data)
        return ticket

    def _await(self, ticket: _Ticket) -> Reply:
        while not ticket.done.is_set():
            if self._read_lock.acquire(timeout=_WAIT_S):
                try:
                    if not ticket.done.is_set():
                        self._pump()
                finally:
                    self._read_lock.release()
        if ticket.error is not None:
            raise ticket.error
        assert ticket.reply is not None
        return ticket.reply

    def _oldest(self) -> _Ticket | None:
        if self._tickets:
            return self._tickets[0]
        return self._fence

    def _pump(self) -> None:
        """Read until one event resolves a ticket, then hand it over."""
        with self._state_lock:
            head = self._oldest()
        if head is None:
            return
        broken = self._conn.state is ClientState.BROKEN and not self._conn.has_events
        if head.is_stop and broken:
            self._pump_stop(head)
            return
        try:
            while True:
                with self._state_lock:
                    event = self._conn.next_event()
                    if event is not None:
                        self._dispatch(event)
                        return
                data = self.link.read_some(head.deadline)
                with self._state_lock:
                    self._conn.receive_data(data)
        except LinkTimeout as exc:
            self._timed_out(head, exc)
        except RemoteProtocolError as exc:
            self.refused_replies += 1
            self._fail_all(RepliesOutOfStep(str(exc)))
        except (LinkError, LocalProtocolError) as exc:
            self._fail_all(exc)

    def _pump_stop(self, head: _Ticket) -> None:
        """Pairing was lost (line noise, a garbled reply) while a STOP was out: its answer
        is the first ``QoK`` read after it went out, whatever came before. None by its own
        deadline: "sent, not confirmed" (`StopNotConfirmed`)."""
        # Replies still owed to the requests sent before the STOP come first: never its.
        seen = self.received_replies - head.after + self.refused_replies - head.refused_after
        skip = max(0, head.ahead - seen)
        try:
            while True:
                with self._state_lock:
                    replies = self._conn.replies_while_broken()
                    dropped, skip = min(skip, len(replies)), max(0, skip - len(replies))
                    answer = next((r for r in replies[dropped:] if isinstance(r, Ok)), None)
                    if answer is not None:
                        for ticket in [t for t in self._tickets if t.is_stop]:
                            self._tickets.remove(ticket)
                            self._resolve(ticket, answer)
                        return
                data = self.link.read_some(head.deadline)
                with self._state_lock:
                    self._conn.receive_data(data)
        except LinkTimeout:
            with self._state_lock:
                if head in self._tickets:
                    self._tickets.remove(head)
                self._reject(head, StopNotConfirmed("STOP was sent; no answer confirmed it"))
        except LinkError as exc:
            self._fail_all(exc)

    def _dispatch(self, event: Paired | Unanswered | Resynced) -> None:
        """Under the state lock."""
        if isinstance(event, Resynced):
            self.dropped_replies += len(event.dropped)
            orphans = [t for t in self._tickets if t.request in event.orphans]
            for ticket in orphans:
                self._tickets.remove(ticket)
                last = event.dropped[-1] if event.dropped else None
                if ticket.is_stop and isinstance(last, Ok):
                    self._resolve(ticket, last)
                else:
                    self._reject(ticket, LinkTimeout("its reply was lost while resynchronising"))
            if self._fence is not None:
                self._resolve(self._fence, Ok("RLNG"))
                self._fence = None
            return
        ticket = next(t for t in self._tickets if t.request is event.request)
        self._tickets.remove(ticket)
        if isinstance(event, Unanswered):
            self._reject(ticket, LinkTimeout(event.reason))
            return
        self.received_replies += 1
        self._last_reply = event.reply
        self._resolve(ticket, event.reply)

    def _timed_out(self, head: _Ticket, exc: LinkTimeout) -> None:
        """The oldest request's deadline passed: it and everything behind it fail, except
        a STOP the controller answered (a reply came after it went out)."""
        error = LinkTimeout(f"no reply to {head.request.command[:40]!r} in time ({exc})")
        with self._state_lock:
            answered_stop = [
                t
                for t in self._tickets
                if t.is_stop
                and self.received_replies - t.after > t.ahead
                and isinstance(self._last_reply, Ok)
            ]
            for ticket in answered_stop:
                self._tickets.remove(ticket)
                assert self._last_reply is not None
                self._resolve(ticket, self._last_reply)
        self._fail_all(error)

    def _resolve(self, ticket: _Ticket, reply: Reply) -> None:
        ticket.reply = reply
        ticket.done.set()

    def _reject(self, ticket: _Ticket, error: BaseException) -> None:
        ticket.error = error
        ticket.done.set()

    def _fail_all(self, error: BaseException) -> None:
        with self._state_lock:
            self._fail_all_locked(error)

    def _fail_all_locked(self, error: BaseException) -> None:
        self._conn.abandon(str(error))
        tickets = list(self._tickets)
        self._tickets.clear()
        if self._fence is not None:
            tickets.append(self._fence)
            self._fence = None
        # A STOP already out keeps waiting for its answer (until its own deadline) when
        # only the pairing was lost; the line itself failing ends it too.
        line_failed = isinstance(error, LinkError) and not isinstance(error, LinkTimeout)
        for ticket in tickets:
            if ticket.is_stop and not line_failed and self._conn.state is ClientState.BROKEN:
                self._tickets.append(ticket)
                continue
            self._reject(ticket, error)
