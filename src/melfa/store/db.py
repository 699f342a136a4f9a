"""A thin layer over sqlite3: one writer thread, per-thread read connections, WAL.

Why this shape (datasette's, see docs/store.md):

* **All writes go one way**: every write runs on one dedicated thread that owns the only
  write connection, inside ``BEGIN IMMEDIATE … COMMIT``. Writes are serialised in process
  without locks in callers, and across processes (the CLI while the server runs) SQLite's
  write lock plus a busy timeout does the rest. A write function called from inside another
  write joins its transaction instead of deadlocking.
* **Reads run on the caller's thread** over a read-only connection of its own; WAL lets them
  proceed while a write is in progress, and each read is one snapshot.
* **Migrations run before first use**: opening a `Database` applies what is pending.
* Parameterised queries only: no function here builds SQL from values.

Async callers use `write_async`/`read_async` (or `melfa.store.AsyncStore`): the writer
thread's future is awaited directly, so the event loop never blocks on the disk.
"""

from __future__ import annotations

import asyncio
import os
import sqlite3
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import TypeVar

from melfa.store.errors import DatabaseError, StoreError
from melfa.store.migrations import MIGRATIONS, Migration
from melfa.store.timeutil import Clock, system_clock, to_text

__all__ = ["BUSY_TIMEOUT_S", "Database", "apply_migrations"]

T = TypeVar("T")

BUSY_TIMEOUT_S = 10.0
"""How long a write waits for another process's write to finish before failing."""


def _configure(conn: sqlite3.Connection) -> sqlite3.Connection:
    conn.row_factory = sqlite3.Row
    conn.execute("PRAGMA foreign_keys = ON")
    return conn


class Database:
    """One SQLite file, opened for use by many threads (see the module docstring)."""

    def __init__(
        self,
        path: Path | str,
        *,
        clock: Clock = system_clock,
        migrations: tuple[Migration, ...] = MIGRATIONS,
    ) -> None:
        self.path = Path(path).resolve()
        self.clock = clock
        self._closed = False
        self._local = threading.local()
        self._readers: list[sqlite3.Connection] = []
        self._readers_lock = threading.Lock()
        self._writer = ThreadPoolExecutor(max_workers=1, thread_name_prefix="melfa-store-writer")
        self._writer_ident = self._writer.submit(threading.get_ident).result()
        try:
            self._conn = self._writer.submit(self._open_writer).result()
            self._writer.submit(apply_migrations, self._conn, migrations, clock).result()
        except sqlite3.Error as err:
            self._writer.submit(self._close_writer).result()
            self._writer.shutdown()
            raise DatabaseError(f"{self.path}: cannot prepare the database: {err}") from err
        except BaseException:
            self._writer.submit(self._close_writer).result()
            self._writer.shutdown()
            raise

    # --- opening and closing --------------------------------------------------------------

    def _open_writer(self) -> sqlite3.Connection:
        if not self.path.parent.is_dir():
            raise DatabaseError(f"{self.path.parent}: no such directory")
        try:
            # Password hashes and session data: readable by the owner only. SQLite gives the
            # -wal and -shm files the same permissions as the database file.
            os.close(os.open(self.path, os.O_RDWR | os.O_CREAT, 0o600))
            conn = sqlite3.connect(self.path, isolation_level=None, timeout=BUSY_TIMEOUT_S)
            _configure(conn)
            conn.execute("PRAGMA journal_mode = WAL")
            # FULL: a committed save survives a power cut, not only a process crash.
            conn.execute("PRAGMA synchronous = FULL")
        except (OSError, sqlite3.Error) as err:
            raise DatabaseError(f"{self.path}: cannot open the database: {err}") from err
        return conn

    def _close_writer(self) -> None:
        conn = getattr(self, "_conn", None)
        if conn is not None:
            conn.close()

    def close(self) -> None:
        """Close every connection; later calls fail. Safe to call twice."""
        if self._closed:
            return
        self._closed = True
        # Readers first: the last connection to close checkpoints and removes the WAL file,
        # and only the writer may.
        with self._readers_lock:
            for conn in self._readers:
                conn.close()
            self._readers.clear()
        self._writer.submit(self._close_writer).result()
        self._writer.shutdown()

    def __enter__(self) -> Database:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _check_open(self) -> None:
        if self._closed:
            raise StoreError("the store is closed")

    # --- writing --------------------------------------------------------------------------

    def _transaction(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        conn = self._conn
        if conn.in_transaction:  # a write inside a write joins it
            return fn(conn)
        try:
            conn.execute("BEGIN IMMEDIATE")
        except sqlite3.Error as err:
            raise DatabaseError(f"{self.path}: cannot start a write: {err}") from err
        try:
            result = fn(conn)
        except BaseException:
            conn.execute("ROLLBACK")
            raise
        try:
            conn.execute("COMMIT")
        except sqlite3.Error as err:
            conn.execute("ROLLBACK")
            raise DatabaseError(f"{self.path}: cannot commit: {err}") from err
        return result

    def _guarded(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        try:
            return self._transaction(fn)
        except StoreError:
            raise
        except sqlite3.Error as err:
            raise DatabaseError(f"{self.path}: {err}") from err

    def write(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """Run `fn(conn)` in one write transaction on the writer thread; all or nothing."""
        self._check_open()
        if threading.get_ident() == self._writer_ident:
            return self._guarded(fn)
        return self._writer.submit(self._guarded, fn).result()

    def submit_write(self, fn: Callable[[sqlite3.Connection], T]) -> Future[T]:
        """Queue a write and return at once (for callers on an event loop that must not wait)."""
        self._check_open()
        return self._writer.submit(self._guarded, fn)

    def flush(self) -> None:
        """Wait until every write queued so far is done."""
        self._check_open()
        if threading.get_ident() != self._writer_ident:
            self._writer.submit(lambda: None).result()

    async def write_async(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """`write` for the event loop: awaits the writer thread without blocking the loop."""
        self._check_open()
        return await asyncio.wrap_future(self._writer.submit(self._guarded, fn))

    # --- reading --------------------------------------------------------------------------

    def _reader(self) -> sqlite3.Connection:
        if threading.get_ident() == self._writer_ident:
            return self._conn  # reads inside a write see the write's own changes
        conn: sqlite3.Connection | None = getattr(self._local, "conn", None)
        if conn is None:
            uri = f"{self.path.as_uri()}?mode=ro"
            conn = sqlite3.connect(
                uri,
                uri=True,
                isolation_level=None,
                timeout=BUSY_TIMEOUT_S,
                check_same_thread=False,  # only so that close() may close it
            )
            _configure(conn)
            with self._readers_lock:
                self._readers.append(conn)
            self._local.conn = conn
        return conn

    def read(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """Run `fn(conn)` on this thread against one consistent snapshot."""
        self._check_open()
        conn = self._reader()
        if conn.in_transaction:
            return fn(conn)
        try:
            conn.execute("BEGIN")
            try:
                return fn(conn)
            finally:
                conn.execute("ROLLBACK")
        except StoreError:
            raise
        except sqlite3.Error as err:
            raise DatabaseError(f"{self.path}: {err}") from err

    async def read_async(self, fn: Callable[[sqlite3.Connection], T]) -> T:
        """`read` on a worker thread."""
        return await asyncio.to_thread(self.read, fn)

    def applied_migrations(self) -> list[str]:
        """Names of the applied migrations, in order."""
        return self.read(
            lambda c: [r[0] for r in c.execute("SELECT name FROM migrations ORDER BY name")]
        )


def apply_migrations(
    conn: sqlite3.Connection,
    migrations: tuple[Migration, ...] = MIGRATIONS,
    clock: Clock = system_clock,
) -> list[str]:
    """Apply the pending migrations in one transaction; return their names.

    Refuses a database that a newer melfa migrated, or whose recorded migrations differ
    from ours (an edited shipped migration): guessing there could destroy work.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "CREATE TABLE IF NOT EXISTS migrations ("
            " name TEXT PRIMARY KEY, checksum TEXT NOT NULL, applied TEXT NOT NULL)"
        )
        applied = {row[0]: row[1] for row in conn.execute("SELECT name, checksum FROM migrations")}
        names = [m.name for m in migrations]
        unknown = sorted(set(applied) - set(names))
        if unknown:
            raise DatabaseError(
                f"the database has migrations this melfa does not know ({', '.join(unknown)}); "
                "it was made by a newer melfa"
            )
        done: list[str] = []
        for migration in migrations:
            if migration.name in applied:
                if applied[migration.name] != migration.checksum:
                    raise DatabaseError(
                        f"migration {migration.name} differs from the one applied to this "
                        "database; shipped migrations must never be edited"
                    )
                if done:
                    raise DatabaseError(
                        f"migration {migration.name} is applied but {done[0]} before it is "
                        "not; the migration list was reordered"
                    )
                continue
            for statement in migration.statements:
                conn.execute(statement)
            conn.execute(
                "INSERT INTO migrations (name, checksum, applied) VALUES (?, ?, ?)",
                (migration.name, migration.checksum, to_text(clock())),
            )
            done.append(migration.name)
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return done
