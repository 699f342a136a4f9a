"""Open sockets and the sessions behind them: a revoked session's socket is closed at once.

Every `/api/ws` and `/rosbridge` connection registers here with its session. Sign-out,
a password change, a role change and an account's removal in this server revoke at once
(`revoke_session`, `revoke_user`): the socket is marked dead (so a message already read is
refused) and closed. Changes made elsewhere (`melfa users` in another process) and expiry
are found by `sweep`, which re-reads every open socket's session every
`Limits.socket_recheck_s`, and by the sockets themselves, which re-read their session
before anything that moves the arm. Caps on open sockets per user and overall live here too.
The same revocations forget the session where a STOP would find it in memory (`known`,
`melfa.web.known_sessions`).
"""

from __future__ import annotations

import asyncio
import contextlib
import ctypes
import datetime as dt
import logging
from collections.abc import Awaitable, Callable, Iterator
from dataclasses import dataclass, field

from melfa.store import Session
from melfa.web.known_sessions import KnownSessions
from melfa.web.limits import Limits, RateMeter, json_too_deep

_log = logging.getLogger("melfa.web.guard")

Closer = Callable[[str], Awaitable[None]]


class TooManySockets(Exception):
    """A connection cap is reached (per user or overall)."""


@dataclass(eq=False)
class SocketHandle:
    """One open socket's session, as last confirmed."""

    session_id: str
    token: str
    user: str
    role: str
    expires: dt.datetime
    close: Closer
    kind: str = "ws"
    revoked: str | None = None
    """Why it may no longer act (None while it may)."""

    def alive(self, now: dt.datetime) -> bool:
        if self.revoked is None and now >= self.expires:
            self.revoked = "the session expired"
        return self.revoked is None


@dataclass
class SocketGuard:
    max_per_user: int = 8
    max_total: int = 200
    max_signing_in: int = 32
    handles: set[SocketHandle] = field(default_factory=set)
    signing_in: int = 0
    """Sockets accepted but not yet signed in (`before_sign_in`)."""
    known: KnownSessions = field(default_factory=KnownSessions)
    """The sessions a STOP is answered from without the store: revoked with the sockets."""
    _tasks: set[asyncio.Task[None]] = field(default_factory=set)

    @contextlib.contextmanager
    def before_sign_in(self) -> Iterator[bool]:
        """Held while a socket signs in: False (refuse it) when too many are signing in or
        the server's sockets are all taken, counting these."""
        if (
            self.signing_in >= self.max_signing_in
            or len(self.handles) + self.signing_in >= self.max_total
        ):
            yield False
            return
        self.signing_in += 1
        try:
            yield True
        finally:
            self.signing_in -= 1

    def open(self, session: Session, token: str, close: Closer, kind: str = "ws") -> SocketHandle:
        """Register a socket (`TooManySockets` beyond the caps)."""
        user = session.user.username
        if len(self.handles) >= self.max_total:
            raise TooManySockets(f"the server has {self.max_total} connections open")
        if sum(h.user == user for h in self.handles) >= self.max_per_user:
            raise TooManySockets(f"{user} has {self.max_per_user} connections open")
        handle = SocketHandle(
            session.id, token, user, session.user.role.value, session.expires, close, kind
        )
        self.handles.add(handle)
        return handle

    def close(self, handle: SocketHandle) -> None:
        self.handles.discard(handle)

    def count(self, user: str | None = None) -> int:
        return sum(user is None or h.user == user for h in self.handles)

    def revoke_session(self, session_id: str, reason: str) -> int:
        """End every socket of one session (sign-out); how many."""
        self.known.forget_session(session_id)
        return self._revoke([h for h in self.handles if h.session_id == session_id], reason)

    def revoke_user(self, user: str, reason: str, *, keep_session: str | None = None) -> int:
        """End every socket of one user (password or role change, removal), except those
        of ``keep_session`` (the session that changed its own password)."""
        self.known.forget_user(user, keep_session=keep_session)
        hit = [h for h in self.handles if h.user == user and h.session_id != keep_session]
        return self._revoke(hit, reason)

    def confirm(self, handle: SocketHandle, session: Session | None) -> bool:
        """A fresh read of the handle's session: still the same person with the same role?"""
        if session is None:
            self._revoke([handle], "the session ended")
        elif session.user.role.value != handle.role:
            self._revoke([handle], "the account's role changed")
        else:
            handle.expires = session.expires
        return handle.revoked is None

    async def sweep(self, lookup: Callable[[str], Awaitable[Session | None]]) -> None:
        """Re-read the session of every open socket (changes made by another process,
        idle expiry); close the dead ones."""
        now = dt.datetime.now(dt.UTC)
        for handle in list(self.handles):
            if not handle.alive(now):
                self._revoke([handle], handle.revoked or "the session ended")
                continue
            with contextlib.suppress(Exception):
                self.confirm(handle, await lookup(handle.token))

    def _revoke(self, handles: list[SocketHandle], reason: str) -> int:
        for handle in handles:
            handle.revoked = handle.revoked or reason
            self.handles.discard(handle)
            _log.info("closing a %s socket of %s: %s", handle.kind, handle.user, reason)
            task = asyncio.ensure_future(handle.close(reason))
            self._tasks.add(task)
            task.add_done_callback(self._tasks.discard)
        return len(handles)


class MessageGate:
    """The checks every message of one socket passes before anything is done with it: its
    session still lives, the rate is kept, the JSON is not too deep. (`melfa.ros`'s
    rosbridge `Gate`; /api/ws uses it too.)"""

    def __init__(self, guard: SocketGuard, handle: SocketHandle, limits: Limits) -> None:
        self.guard = guard
        self.handle = handle
        self.limits = limits
        self.meter = RateMeter(limits.ws_messages_per_s, limits.ws_burst)
        self.closing = False

    def check(self, text: str) -> str | None:
        if not self.handle.alive(dt.datetime.now(dt.UTC)):
            self.closing = True
            return f"this connection's session has ended ({self.handle.revoked})"
        if not self.meter.allow():
            self.closing = True
            return (
                f"more than {self.limits.ws_messages_per_s:g} messages a second "
                f"(burst {self.limits.ws_burst}): connection closed"
            )
        if json_too_deep(text, self.limits.json_depth):
            return f"the message nests deeper than {self.limits.json_depth} levels"
        return None

    def close(self) -> None:
        self.guard.close(self.handle)
        if self.handle.kind == "rosbridge":
            give_memory_back()


def give_memory_back() -> None:
    """Return freed heap memory to the system (glibc's ``malloc_trim``; elsewhere nothing):
    a /rosbridge socket may have carried hundreds of megabytes of large messages, which
    Python frees but the C allocator keeps, so the server's memory would stay at its peak."""
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:
        return
    with contextlib.suppress(AttributeError):
        libc.malloc_trim(0)


__all__ = ["MessageGate", "SocketGuard", "SocketHandle", "TooManySockets"]
