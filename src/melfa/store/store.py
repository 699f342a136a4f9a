"""`Store`: one database file and everything kept in it, plus an async front for the web."""

from __future__ import annotations

import asyncio
import os
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import ParamSpec, TypeVar

from argon2 import PasswordHasher

from melfa.store.accounts import Accounts
from melfa.store.assignments import Assignments
from melfa.store.audit import AuditLog
from melfa.store.db import Database
from melfa.store.errors import DatabaseError
from melfa.store.models import RateLimit
from melfa.store.passwords import Passwords
from melfa.store.preflights import Preflights
from melfa.store.queues import QueueDocs
from melfa.store.robot_settings import RobotSettings
from melfa.store.runs import Runs
from melfa.store.sessions import LoginAttempts, LoginPolicy, SessionPolicy, Sessions
from melfa.store.thinning import Retention
from melfa.store.timeutil import Clock, system_clock
from melfa.store.tokens import AccessTokens
from melfa.store.workspaces import Workspaces

__all__ = [
    "DATABASE_FILENAME",
    "DATA_ENV",
    "AsyncStore",
    "Store",
    "database_path",
    "default_data_dir",
]

P = ParamSpec("P")
T = TypeVar("T")

DATA_ENV = "MELFA_DATA"
DATABASE_FILENAME = "melfa.sqlite3"


def default_data_dir() -> Path:
    """``$MELFA_DATA``, else ``./data``."""
    return Path(os.environ.get(DATA_ENV) or "data")


def database_path(data_dir: Path | str) -> Path:
    """Where the database lives inside a data directory."""
    return Path(data_dir) / DATABASE_FILENAME


class Store:
    """Accounts, sessions, login attempts, workspaces, assignments, the audit log,
    recorded runs, passed pre-flights, the shared robots' queues and desk settings of one file.

    Opening applies pending migrations. Every part is safe to use from many threads.
    """

    def __init__(
        self,
        path: Path | str,
        *,
        clock: Clock = system_clock,
        hasher: PasswordHasher | None = None,
        session_policy: SessionPolicy | None = None,
        login_policy: LoginPolicy | None = None,
        retention: Retention | None = None,
        run_retention: Retention | None = None,
    ) -> None:
        self.db = Database(path, clock=clock)
        self.passwords = Passwords(hasher)
        self.accounts = Accounts(self.db, self.passwords)
        self.sessions = Sessions(self.db, self.accounts, session_policy)
        self.logins = LoginAttempts(self.db, login_policy)
        self.workspaces = Workspaces(self.db, self.accounts, retention)
        self.audit = AuditLog(self.db)
        self.tokens = AccessTokens(self.db, self.accounts)
        self.assignments = Assignments(self.db, self.workspaces)
        self.runs = Runs(self.db, run_retention)
        self.preflights = Preflights(self.db)
        self.queues = QueueDocs(self.db)
        self.robot_settings = RobotSettings(self.db)

    @classmethod
    def open_dir(cls, data_dir: Path | str, *, create: bool = True, **options: object) -> Store:
        """The store in `data_dir` (``DIR/melfa.sqlite3``); the directory is made private.

        With ``create=False`` a missing database is an error instead of a new one.
        """
        directory = Path(data_dir)
        path = database_path(directory)
        if not create and not path.is_file():
            raise DatabaseError(f"no database at {path}")
        try:
            directory.mkdir(mode=0o700, parents=True, exist_ok=True)
        except OSError as err:
            raise DatabaseError(f"{directory}: cannot create the data directory: {err}") from err
        return cls(path, **options)  # type: ignore[arg-type]

    @property
    def path(self) -> Path:
        return self.db.path

    def login_allowed(self, username: str, addr: str, now: datetime | None = None) -> RateLimit:
        """Whether a login for `username` from `addr` may be tried now (rate limiting)."""
        return self.logins.login_allowed(username, addr, now)

    def close(self) -> None:
        self.db.close()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class AsyncStore:
    """The store for an event loop: ``await astore.call(store.accounts.authenticate, u, p)``.

    Each call runs on a worker thread (password hashing and reads included), so the loop
    never waits on the disk or on Argon2; the writes inside still go through the store's one
    writer thread, in order.
    """

    def __init__(self, store: Store) -> None:
        self.store = store

    async def call(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        return await asyncio.to_thread(fn, *args, **kwargs)
