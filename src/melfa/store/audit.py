"""The audit log: append-only record of what moved the arm and who asked (design.md).

The table refuses UPDATE and DELETE by trigger, so even a bug here cannot rewrite
history. Entries are numbered in insertion order; pages are cut by that number (keyset
paging), so new events arriving while an instructor pages back shift nothing.
"""

from __future__ import annotations

import dataclasses
import enum
import json
import sqlite3
from datetime import datetime
from typing import Any

from melfa.store.db import Database
from melfa.store.models import AuditEntry, AuditEvent, AuditPage
from melfa.store.timeutil import from_text, to_text

__all__ = ["MAX_PAGE", "AuditLog", "insert_event"]

MAX_PAGE = 500


def _jsonable(value: object) -> object:
    """Fallback for `json.dumps`: enums by value, times as ISO text, the rest as text."""
    if isinstance(value, enum.Enum):
        return value.value
    if isinstance(value, datetime):
        return value.isoformat()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return dataclasses.asdict(value)
    if isinstance(value, (set, frozenset, tuple)):
        return list(value)
    return str(value)


def _entry(row: sqlite3.Row) -> AuditEntry:
    details: dict[str, Any] = json.loads(row["details"])
    return AuditEntry(
        row["id"],
        from_text(row["at"]),
        row["actor"],
        row["role"],
        row["action"],
        details,
        row["result"],
    )


class AuditLog:
    """Append and query audit events. `record` makes this an audit sink for the service."""

    def __init__(self, db: Database) -> None:
        self.db = db

    def record(self, event: AuditEvent) -> int:
        """Append one event; returns its sequence id."""
        at = event.at if event.at is not None else self.db.clock()
        return self.db.write(lambda conn: insert_event(conn, dataclasses.replace(event, at=at)))

    async def record_async(self, event: AuditEvent) -> int:
        """`record` from the event loop."""
        at = event.at if event.at is not None else self.db.clock()
        return await self.db.write_async(
            lambda conn: insert_event(conn, dataclasses.replace(event, at=at))
        )

    def query(
        self,
        *,
        since: datetime | None = None,
        until: datetime | None = None,
        actor: str | None = None,
        action: str | None = None,
        robot: str | None = None,
        limit: int = 50,
        before: int | None = None,
    ) -> AuditPage:
        """Entries newest first, filtered by time range [since, until), actor, action and
        robot (``details.robot``: one robot's log, `melfa.vocab.robot_log`).

        Pass the page's `next_before` as `before` for the next (older) page.
        """
        limit = max(1, min(limit, MAX_PAGE))
        clauses: list[str] = []
        params: list[object] = []
        if since is not None:
            clauses.append("at >= ?")
            params.append(to_text(since))
        if until is not None:
            clauses.append("at < ?")
            params.append(to_text(until))
        if actor is not None:
            clauses.append("actor = ?")
            params.append(actor)
        if action is not None:
            clauses.append("action = ?")
            params.append(action)
        if robot is not None:
            clauses.append("json_extract(details, '$.robot') = ?")
            params.append(robot)
        if before is not None:
            clauses.append("id < ?")
            params.append(before)
        where = (" WHERE " + " AND ".join(clauses)) if clauses else ""
        params.append(limit + 1)
        rows = self.db.read(
            lambda c: c.execute(
                "SELECT * FROM audit" + where + " ORDER BY id DESC LIMIT ?", params
            ).fetchall()
        )
        entries = tuple(_entry(r) for r in rows[:limit])
        more = len(rows) > limit
        return AuditPage(entries, entries[-1].id if more and entries else None)


def insert_event(conn: sqlite3.Connection, event: AuditEvent) -> int:
    """Append inside a caller's write (the service sink queues this on the writer)."""
    assert event.at is not None
    details = json.dumps(event.details, default=_jsonable, sort_keys=True)
    cur = conn.execute(
        "INSERT INTO audit (at, actor, role, action, details, result) VALUES (?, ?, ?, ?, ?, ?)",
        (to_text(event.at), event.actor, event.role, event.action, details, event.result),
    )
    assert cur.lastrowid is not None
    return cur.lastrowid
