"""Personal access tokens: long-lived credentials for programs (roslibjs pages, roslibpy
scripts, ``curl``) that cannot sign in with a password and a cookie.

``melfa users token NAME`` (or the IDE's user menu) makes one and shows it once; the
database keeps only its SHA-256, like session tokens. A token acts as its owner, with the
owner's role, until revoked (or the account is disabled or removed). Where it is accepted:
``?token=`` in a WebSocket URL, rosbridge's ``auth`` op, ``Authorization: Bearer`` on the
REST API (docs/security.md). A token looks like ``melfa_pat_…`` so it is recognisable in a
leaked log and never confused with a session cookie.
"""

from __future__ import annotations

import secrets
import sqlite3
from dataclasses import dataclass
from datetime import datetime, timedelta

from melfa.store.accounts import Accounts
from melfa.store.db import Database
from melfa.store.errors import NotFound
from melfa.store.models import Session, User
from melfa.store.sessions import hash_token
from melfa.store.timeutil import from_text, to_text

PREFIX = "melfa_pat_"
"""Every token starts with this."""
LOOKUP_VALID_FOR = timedelta(days=1)
"""A looked-up token's `Session.expires`: tokens live until revoked, and whoever holds a
session re-reads it (the socket guard every few seconds), which moves this on."""
MAX_LABEL = 60


@dataclass(frozen=True, slots=True)
class AccessToken:
    """A token as listed: never the token itself."""

    id: int
    username: str
    label: str
    created: datetime
    last_used: datetime | None


@dataclass(frozen=True, slots=True)
class NewAccessToken:
    """A token just made: `token` is shown only this once."""

    token: str
    info: AccessToken


def is_access_token(token: str | None) -> bool:
    """Whether ``token`` has the personal-access-token form (not a session token)."""
    return bool(token) and str(token).startswith(PREFIX)


class AccessTokens:
    """Create, look up, list and revoke personal access tokens."""

    def __init__(self, db: Database, accounts: Accounts) -> None:
        self.db = db
        self.accounts = accounts

    def create(self, user: User, label: str = "") -> NewAccessToken:
        label = " ".join(label.split())[:MAX_LABEL] or "token"
        token = PREFIX + secrets.token_urlsafe(32)
        now = self.db.clock()
        cur = self.db.write(
            lambda conn: conn.execute(
                "INSERT INTO access_tokens (token_hash, user_id, label, created)"
                " VALUES (?, ?, ?, ?)",
                (hash_token(token), user.id, label, to_text(now)),
            )
        )
        info = AccessToken(int(cur.lastrowid or 0), user.username, label, now, None)
        return NewAccessToken(token, info)

    def lookup(self, token: str | None) -> Session | None:
        """The token as a `Session` of its owner (id ``pat-<n>``; its CSRF token is unusable:
        a token is sent by programs, never by a browser's cookie jar), or None."""
        if not is_access_token(token) or len(str(token)) > 256:
            return None
        key = hash_token(str(token))
        row = self.db.read(
            lambda conn: conn.execute(
                "SELECT * FROM access_tokens WHERE token_hash = ?", (key,)
            ).fetchone()
        )
        if row is None:
            return None
        user = self.accounts.get_user_by_id(row["user_id"])
        if user is None or user.disabled:
            return None
        now = self.db.clock()
        last = row["last_used"]
        if last is None or (now - from_text(last)).total_seconds() >= 60:
            self.db.write(
                lambda conn: conn.execute(
                    "UPDATE access_tokens SET last_used = ? WHERE id = ?", (to_text(now), row["id"])
                )
            )
        created = from_text(row["created"])
        expires = now + LOOKUP_VALID_FOR  # renewed at every lookup: no expiry of its own
        return Session(
            f"pat-{row['id']}", user, secrets.token_urlsafe(32), created, expires, now, None
        )

    def list(self, user: User) -> list[AccessToken]:
        rows = self.db.read(
            lambda conn: conn.execute(
                "SELECT * FROM access_tokens WHERE user_id = ? ORDER BY id", (user.id,)
            ).fetchall()
        )
        return [_info(row, user.username) for row in rows]

    def revoke(self, user: User, token_id: int) -> AccessToken:
        """Revoke one of ``user``'s tokens by its number; `NotFound` when it has none such."""
        found = [t for t in self.list(user) if t.id == token_id]
        if not found:
            raise NotFound(f"{user.username} has no token number {token_id}")
        self.db.write(
            lambda conn: conn.execute(
                "DELETE FROM access_tokens WHERE id = ? AND user_id = ?", (token_id, user.id)
            )
        )
        return found[0]


def _info(row: sqlite3.Row, username: str) -> AccessToken:
    last = row["last_used"]
    return AccessToken(
        row["id"],
        username,
        row["label"],
        from_text(row["created"]),
        None if last is None else from_text(last),
    )


__all__ = ["PREFIX", "AccessToken", "AccessTokens", "NewAccessToken", "is_access_token"]
