"""Login throttling that slows guessing without locking anyone out.

An attempt is recorded (as a failure) and the limits checked in ONE write transaction
before the password is looked at (`LoginAttempts.begin`), so a hundred concurrent guesses
are counted one after another and at most the allowed number reach the password check;
`finish` marks it a success. Three counters, each with exponential back-off once its free
failures are spent (never a fixed lock-out):

- per **address**, over all accounts (a guesser trying many accounts);
- per **account from unfamiliar addresses** (a guesser aiming at one account);
- per **account from one of its usual addresses** — an address it signed in from
  successfully before. Failures elsewhere never count here, so a locked-out attacker does
  not lock out the owner at their usual computer; the owner's own typos back off alone.

The wait is ``backoff_base · 2^(failures − free)`` after the last failure, at most
``backoff_max``; failures older than ``window`` no longer count.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from datetime import datetime, timedelta

from melfa.store.db import Database
from melfa.store.models import RateLimit
from melfa.store.timeutil import from_text, to_text

__all__ = ["LoginAttempts", "LoginPolicy", "LoginTicket", "backoff"]

_MAX_KEY = 64  # usernames and addresses longer than this are cut before storing


@dataclass(frozen=True, slots=True)
class LoginPolicy:
    window: timedelta = timedelta(minutes=15)
    """Failures older than this no longer count (a sliding window)."""
    max_failures_per_user: int = 5
    """Free failures on one account from unfamiliar addresses before back-off."""
    max_failures_per_addr: int = 30
    """Free failures from one address (any account); higher than per user: a lab's
    computers may share one address behind NAT."""
    max_failures_usual: int = 5
    """Free failures on one account from one of its usual addresses."""
    backoff_base: timedelta = timedelta(seconds=2)
    backoff_max: timedelta = timedelta(minutes=5)
    usual_for: timedelta = timedelta(days=90)
    """An address stays "usual" for an account this long after a successful sign-in."""


@dataclass(frozen=True, slots=True)
class LoginTicket:
    """One admitted attempt, already counted as a failure until `finish` says otherwise."""

    attempt_id: int
    username: str
    client_addr: str


def backoff(failures: int, free: int, policy: LoginPolicy) -> timedelta:
    """How long after the last failure the next attempt must wait.

    >>> p = LoginPolicy()
    >>> [backoff(n, 5, p).total_seconds() for n in (4, 5, 7, 40)]
    [0.0, 2.0, 8.0, 300.0]
    """
    if failures < free:
        return timedelta(0)
    extra = min(failures - free, 30)
    wait: timedelta = min(policy.backoff_base * (2**extra), policy.backoff_max)
    return wait


def _keys(username: str, client_addr: str) -> tuple[str, str]:
    return username.strip().lower()[:_MAX_KEY], client_addr[:_MAX_KEY]


class LoginAttempts:
    """Record attempts and decide, atomically, whether one more may try a password."""

    def __init__(self, db: Database, policy: LoginPolicy | None = None) -> None:
        self.db = db
        self.policy = policy if policy is not None else LoginPolicy()

    # ------------------------------------------------------------------ the decision

    def _decide(self, conn: sqlite3.Connection, user: str, addr: str, now: datetime) -> RateLimit:
        p = self.policy
        since = to_text(now - p.window)
        usual = conn.execute(
            "SELECT 1 FROM login_addresses WHERE username = ? AND client_addr = ?"
            " AND last_success > ?",
            (user, addr, to_text(now - p.usual_for)),
        ).fetchone()
        counters: list[tuple[str, tuple[object, ...], int, str]] = []
        if usual:
            counters.append(
                (
                    "username = ? AND client_addr = ?",
                    (user, addr),
                    p.max_failures_usual,
                    "too many failed sign-ins for this account from this computer",
                )
            )
        else:
            counters.append(
                (
                    "username = ? AND client_addr NOT IN (SELECT client_addr FROM"
                    " login_addresses WHERE username = ? AND last_success > ?)",
                    (user, user, to_text(now - p.usual_for)),
                    p.max_failures_per_user,
                    "too many failed sign-ins for this account",
                )
            )
            counters.append(
                (
                    "client_addr = ?",
                    (addr,),
                    p.max_failures_per_addr,
                    "too many failed sign-ins from this address",
                )
            )
        for where, params, free, reason in counters:
            row = conn.execute(
                f"SELECT COUNT(*), MAX(at) FROM login_attempts WHERE success = 0 AND at > ?"
                f" AND {where}",
                (since, *params),
            ).fetchone()
            count, last = row[0], row[1]
            wait = backoff(count, free, p)
            if wait and last is not None:
                until = from_text(last) + wait
                if until > now:
                    return RateLimit(False, until - now, reason)
        return RateLimit(True)

    def begin(
        self, username: str, client_addr: str, now: datetime | None = None
    ) -> LoginTicket | RateLimit:
        """Admit one attempt (recorded as a failure now) or refuse it with the wait."""
        moment = now if now is not None else self.db.clock()
        user, addr = _keys(username, client_addr)

        def admit(conn: sqlite3.Connection) -> LoginTicket | RateLimit:
            conn.execute(
                "DELETE FROM login_attempts WHERE at < ?", (to_text(moment - self.policy.window),)
            )
            decision = self._decide(conn, user, addr, moment)
            if not decision:
                return decision
            cur = conn.execute(
                "INSERT INTO login_attempts (username, client_addr, at, success)"
                " VALUES (?, ?, ?, 0)",
                (user, addr, to_text(moment)),
            )
            return LoginTicket(int(cur.lastrowid or 0), user, addr)

        return self.db.write(admit)

    def finish(self, ticket: LoginTicket, success: bool, now: datetime | None = None) -> None:
        """The password was checked: a success forgives the account's failures from this
        address and makes the address usual for it."""
        if not success:
            return
        moment = now if now is not None else self.db.clock()

        def note(conn: sqlite3.Connection) -> None:
            conn.execute("UPDATE login_attempts SET success = 1 WHERE id = ?", (ticket.attempt_id,))
            conn.execute(
                "DELETE FROM login_attempts WHERE username = ? AND client_addr = ? AND success = 0",
                (ticket.username, ticket.client_addr),
            )
            conn.execute(
                "INSERT INTO login_addresses (username, client_addr, last_success)"
                " VALUES (?, ?, ?) ON CONFLICT (username, client_addr)"
                " DO UPDATE SET last_success = excluded.last_success",
                (ticket.username, ticket.client_addr, to_text(moment)),
            )

        self.db.write(note)

    def cancel(self, ticket: LoginTicket) -> None:
        """The password was never checked (the server was too busy): forget the attempt."""
        self.db.write(
            lambda conn: conn.execute(
                "DELETE FROM login_attempts WHERE id = ?", (ticket.attempt_id,)
            )
        )

    # ------------------------------------------------------------------ older interface

    def record(
        self, username: str, client_addr: str, success: bool, now: datetime | None = None
    ) -> None:
        """Note one finished attempt (begin + finish without the limit), for imports and
        tests."""
        moment = now if now is not None else self.db.clock()
        user, addr = _keys(username, client_addr)
        cur = self.db.write(
            lambda conn: conn.execute(
                "INSERT INTO login_attempts (username, client_addr, at, success)"
                " VALUES (?, ?, ?, 0)",
                (user, addr, to_text(moment)),
            )
        )
        self.finish(LoginTicket(int(cur.lastrowid or 0), user, addr), success, moment)

    def login_allowed(
        self, username: str, client_addr: str, now: datetime | None = None
    ) -> RateLimit:
        """Whether another attempt may be made now (without admitting one)."""
        moment = now if now is not None else self.db.clock()
        user, addr = _keys(username, client_addr)
        return self.db.read(lambda conn: self._decide(conn, user, addr, moment))
