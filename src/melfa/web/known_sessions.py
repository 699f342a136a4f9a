"""The sessions a STOP may be answered from without reading the store.

STOP is allowed to every signed-in user, and a session revoked a moment ago that stops the
arm harms no one; so a STOP need not wait for a store thread to confirm its session (on
two busy cores every hop to a thread and back waits for the CPU, the GIL and the event
loop again). `KnownSessions` holds the sessions this server confirmed recently, by token:
every signed-in request confirms its own (`melfa.web.deps`). Only STOP reads it; every
other request still reads its session from the store, so sign-out and revocation stay
exact for them.

In this server, sign-out, a password change, an account's removal and a token's revocation
forget at once (`SocketGuard.revoke_session` / `revoke_user`, with the sockets). What
another process changes (`melfa users`) and idle expiry are found when an entry is read
again: a STOP answered from an entry older than ``fresh_s`` (`Limits.socket_recheck_s`,
as open sockets) re-reads it once answered, and an entry not confirmed for ``keep_s``
(`Limits.stop_session_memory_s`) is not used. Pure bookkeeping: no I/O, a clock passed in.
"""

from __future__ import annotations

import datetime as dt
import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass, field

from melfa.store import Session


@dataclass(frozen=True, slots=True)
class Recalled:
    """A session found in memory; ``stale`` when it should be read again after use."""

    session: Session
    stale: bool


@dataclass
class KnownSessions:
    fresh_s: float = 2.0
    """Older than this, an entry used is read again afterwards."""
    keep_s: float = 60.0
    """Older than this, an entry is not used (the store is read)."""
    capacity: int = 4096
    """Entries kept (the least recently confirmed go first)."""
    clock: Callable[[], float] = time.monotonic
    now_utc: Callable[[], dt.datetime] = lambda: dt.datetime.now(dt.UTC)
    """For the session's absolute expiry."""
    _known: OrderedDict[str, tuple[Session, float]] = field(default_factory=OrderedDict)

    def remember(self, token: str, session: Session) -> None:
        """``session`` was just read from the store for ``token``."""
        self._known[token] = (session, self.clock())
        self._known.move_to_end(token)
        while len(self._known) > self.capacity:
            self._known.popitem(last=False)

    def recall(self, token: str) -> Recalled | None:
        """The session of ``token`` when confirmed within ``keep_s`` and not expired."""
        entry = self._known.get(token)
        if entry is None:
            return None
        session, confirmed = entry
        age = self.clock() - confirmed
        if age >= self.keep_s or self.now_utc() >= session.expires:
            del self._known[token]
            return None
        return Recalled(session, age >= self.fresh_s)

    def forget(self, token: str) -> None:
        self._known.pop(token, None)

    def forget_session(self, session_id: str) -> None:
        for token in [t for t, (s, _) in self._known.items() if s.id == session_id]:
            del self._known[token]

    def forget_user(self, user: str, *, keep_session: str | None = None) -> None:
        """Every session of ``user`` but ``keep_session``."""
        for token in [
            t
            for t, (s, _) in self._known.items()
            if s.user.username == user and s.id != keep_session
        ]:
            del self._known[token]

    def __len__(self) -> int:
        return len(self._known)


__all__ = ["KnownSessions", "Recalled"]
