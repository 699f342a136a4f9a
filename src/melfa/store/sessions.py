"""Server-side login sessions and CSRF tokens (login throttling: `melfa.store.logins`).

The cookie carries a random token; the database keeps only its SHA-256, so a copy of the
database (a backup, a stolen laptop) holds no usable session. Each session has its own
CSRF token, which the web layer puts in pages and checks on state-changing requests.

A session ends at the first of: its absolute lifetime, an idle timeout, logout, a password
change, the account being disabled or removed.
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
from dataclasses import dataclass
from datetime import timedelta

from melfa.store.accounts import Accounts
from melfa.store.db import Database
from melfa.store.logins import LoginAttempts, LoginPolicy
from melfa.store.models import NewSession, Session, User
from melfa.store.timeutil import from_text, to_text

__all__ = [
    "LoginAttempts",
    "LoginPolicy",
    "SessionPolicy",
    "Sessions",
    "check_csrf",
    "hash_token",
]

_MAX_KEY = 64  # usernames and addresses longer than this are cut before storing


@dataclass(frozen=True, slots=True)
class SessionPolicy:
    lifetime: timedelta = timedelta(hours=12)
    """A lab day; then sign in again."""
    idle_timeout: timedelta = timedelta(hours=2)
    touch_interval: timedelta = timedelta(minutes=1)
    """`last_seen` is written at most this often, so reads do not each cost a write."""


def hash_token(token: str) -> str:
    """What is stored for a cookie token."""
    return hashlib.sha256(token.encode()).hexdigest()


def check_csrf(session: Session, token: str | None) -> bool:
    """True when `token` is this session's CSRF token (compared in constant time)."""
    return token is not None and hmac.compare_digest(session.csrf_token, token)


class Sessions:
    """Create, look up and revoke sessions."""

    def __init__(
        self, db: Database, accounts: Accounts, policy: SessionPolicy | None = None
    ) -> None:
        self.db = db
        self.accounts = accounts
        self.policy = policy if policy is not None else SessionPolicy()

    def create(self, user: User, client_addr: str | None = None) -> NewSession:
        """A new session for `user`; the returned token is the only copy."""
        token = secrets.token_urlsafe(32)
        csrf = secrets.token_urlsafe(32)
        now = self.db.clock()
        expires = now + self.policy.lifetime
        addr = None if client_addr is None else client_addr[:_MAX_KEY]
        self.db.write(
            lambda conn: conn.execute(
                "INSERT INTO sessions (token_hash, user_id, csrf_token, created, expires,"
                " last_seen, client_addr) VALUES (?, ?, ?, ?, ?, ?, ?)",
                (
                    hash_token(token),
                    user.id,
                    csrf,
                    to_text(now),
                    to_text(expires),
                    to_text(now),
                    addr,
                ),
            )
        )
        session = Session(hash_token(token), user, csrf, now, expires, now, addr)
        return NewSession(token, session)

    def lookup(self, token: str | None, *, touch: bool = True) -> Session | None:
        """The live session for a cookie token, or None (unknown, expired, idle, disabled).
        ``touch=False`` never writes (a STOP's lookup must not wait for the writer)."""
        if not token or len(token) > 256:
            return None
        key = hash_token(token)
        row = self.db.read(
            lambda conn: conn.execute(
                "SELECT * FROM sessions WHERE token_hash = ?", (key,)
            ).fetchone()
        )
        if row is None:
            return None
        now = self.db.clock()
        last_seen = from_text(row["last_seen"])
        if now >= from_text(row["expires"]) or now - last_seen >= self.policy.idle_timeout:
            return None
        user = self.accounts.get_user_by_id(row["user_id"])
        if user is None or user.disabled:
            return None
        if touch and now - last_seen >= self.policy.touch_interval:
            last_seen = now
            self.db.write(
                lambda conn: conn.execute(
                    "UPDATE sessions SET last_seen = ? WHERE token_hash = ?", (to_text(now), key)
                )
            )
        return Session(
            key,
            user,
            row["csrf_token"],
            from_text(row["created"]),
            from_text(row["expires"]),
            last_seen,
            row["client_addr"],
        )

    def revoke(self, token: str) -> bool:
        """End one session (logout); False when there was none."""
        key = hash_token(token)
        return self.revoke_id(key)

    def revoke_id(self, session_id: str) -> bool:
        """End a session by its id (`Session.id`), e.g. from an instructor's list."""
        cur = self.db.write(
            lambda conn: conn.execute("DELETE FROM sessions WHERE token_hash = ?", (session_id,))
        )
        return cur.rowcount > 0

    def revoke_all(self, user_id: int) -> int:
        """End every session of one user; how many there were."""
        cur = self.db.write(
            lambda conn: conn.execute("DELETE FROM sessions WHERE user_id = ?", (user_id,))
        )
        return cur.rowcount

    def revoke_others(self, user_id: int, keep_id: str) -> int:
        """End every session of one user but ``keep_id`` (after changing one's password)."""
        cur = self.db.write(
            lambda conn: conn.execute(
                "DELETE FROM sessions WHERE user_id = ? AND token_hash != ?", (user_id, keep_id)
            )
        )
        return cur.rowcount

    def purge_expired(self) -> int:
        """Delete sessions past their lifetime or idle timeout; how many."""
        now = self.db.clock()
        idle_before = to_text(now - self.policy.idle_timeout)
        cur = self.db.write(
            lambda conn: conn.execute(
                "DELETE FROM sessions WHERE expires <= ? OR last_seen <= ?",
                (to_text(now), idle_before),
            )
        )
        return cur.rowcount
