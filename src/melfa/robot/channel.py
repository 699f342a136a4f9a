"""One link, many threads: requests in turn, except that STOP may overtake.

The worker thread sends one request and waits for its reply. Another thread calling
`Robot.stop` must not wait behind that reply (a 254-byte EMDAT takes ~0.3 s on the wire, a
stuck controller up to the timeout), so the channel *pipelines* STOP: its bytes go out at once,
right after the in-flight request, and the replies are paired with the requests first-in,
first-out (`melfa.protocol.ClientConnection`). Whichever waiting thread holds the read lock
reads replies and hands each to its owner, so neither thread ever reads the other's reply.

Failure rules: a timeout, a garbled reply or a dead link loses the pairing, so *every*
outstanding request fails with that error and the channel drains the line (discarding late
replies) before the next request.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections import deque
from collections.abc import Generator, Iterable
from dataclasses import dataclass, field

from melfa.link import Link, LinkError, LinkTimeout
from melfa.protocol import (
    OVERTAKING_COMMANDS,
    ClientConnection,
    ClientState,
    RemoteProtocolError,
    Reply,
    Request,
)

_WAIT_S = 0.02


@dataclass
class _Ticket:
    request: Request
    deadline: float
    reply: Reply | None = None
    error: BaseException | None = None
    done: threading.Event = field(default_factory=threading.Event)


class Channel:
    """Thread-safe request/reply over a `Link`."""

    def __init__(self, link: Link) -> None:
        self.link = link
        self._conn = ClientConnection()
        self._send_lock = threading.Lock()
        self._read_lock = threading.Lock()
        self._tickets: deque[_Ticket] = deque()
        self._tickets_lock = threading.Lock()
        self.sent_bytes = 0
        self.received_replies = 0

    def request(self, request: Request, timeout: float | None = None) -> Reply:
        """Send ``request`` and return its reply (or raise the link/protocol error).

        Only STOP overtakes: any other request first waits for the replies still
        outstanding (a STOP pipelined by another thread), so that e.g. the ``NEW`` that
        abandons a stopped upload is sent in turn instead of being refused as out of turn.
        """
        if request.command not in OVERTAKING_COMMANDS:
            self._settle()
        return self._await(self._submit(request, timeout))

    def _settle(self) -> None:
        """Wait until no request is outstanding; their owners get the replies or errors."""
        while True:
            with self._tickets_lock:
                if not self._tickets:
                    return
                oldest = self._tickets[0]
            with contextlib.suppress(Exception):  # the owner sees the error, not us
                self._await(oldest)

    def pipeline(
        self, requests: Iterable[Request], window: int, timeout: float | None = None
    ) -> Generator[Reply, None, None]:
        """Send ``requests`` keeping up to ``window`` in flight; yield replies in order.

        If the consumer stops early (a refusal), the replies still in flight are read and
        dropped before the generator closes, so the pairing stays intact.
        """
        pending: deque[_Ticket] = deque()
        source = iter(requests)
        try:
            while True:
                while len(pending) < window:
                    request = next(source, None)
                    if request is None:
                        break
                    pending.append(self._submit(request, timeout, window=window))
                if not pending:
                    return
                yield self._await(pending.popleft())
        finally:
            for ticket in pending:
                with contextlib.suppress(Exception):
                    self._await(ticket)

    def _submit(self, request: Request, timeout: float | None, window: int = 1) -> _Ticket:
        limit = self.link.settings.timeout if timeout is None else timeout
        with self._send_lock:
            if self._conn.state is ClientState.BROKEN and not self._tickets:
                self._resync()
            data = self._conn.send(request, window=window)  # LocalProtocolError if out of turn
            ticket = _Ticket(request, time.monotonic() + limit)
            with self._tickets_lock:
                self._tickets.append(ticket)
            try:
                self.link.write(data)
            except LinkError as exc:
                self._fail_all(exc)
                raise
            self.sent_bytes += len(data)
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

    def _pump(self) -> None:
        """Read until the oldest outstanding request has its reply, then hand it over."""
        with self._tickets_lock:
            if not self._tickets:
                return
            head = self._tickets[0]
        try:
            while True:
                pair = self._conn.next_reply()
                if pair is not None:
                    break
                self._conn.receive_data(self.link.read_some(head.deadline))
        except LinkTimeout as exc:
            self._fail_all(
                LinkTimeout(f"no reply to {head.request.command[:40]!r} in time ({exc})")
            )
            return
        except (LinkError, RemoteProtocolError) as exc:
            self._fail_all(exc)
            return
        with self._tickets_lock:
            ticket = self._tickets.popleft()
        ticket.reply = pair[1]
        self.received_replies += 1
        ticket.done.set()

    def _fail_all(self, error: BaseException) -> None:
        self._conn.abandon(str(error))
        with self._tickets_lock:
            tickets = list(self._tickets)
            self._tickets.clear()
        for ticket in tickets:
            ticket.error = error
            ticket.done.set()

    def _resync(self) -> None:
        """After a lost pairing: drop whatever is still arriving, then start afresh."""
        if not self.link.closed:
            with contextlib.suppress(LinkError):
                self.link.drain(quiet=0.2, limit=2.0)
        self._conn.reset()
