"""Audit log: append-only, filtered queries, keyset paging."""

from __future__ import annotations

import enum
import sqlite3
from datetime import timedelta
from pathlib import Path

import pytest

from melfa.store import AuditEvent, DatabaseError, Store
from tests.store.conftest import FakeClock


class Kind(enum.Enum):
    MOVE = "move"


def test_append_and_read_back(store: Store, clock: FakeClock) -> None:
    event_id = store.audit.record(
        AuditEvent(
            "robot.run",
            actor="ada",
            role="student",
            details={"slot": 1, "kind": Kind.MOVE, "when": clock.now},
            result="ok",
        )
    )
    page = store.audit.query()
    assert [e.id for e in page.entries] == [event_id]
    entry = page.entries[0]
    assert (entry.action, entry.actor, entry.role, entry.result) == (
        "robot.run",
        "ada",
        "student",
        "ok",
    )
    assert entry.details == {"slot": 1, "kind": "move", "when": clock.now.isoformat()}
    assert entry.at == clock.now
    assert page.next_before is None


def test_query_filters(store: Store, clock: FakeClock) -> None:
    t0 = clock.now
    store.audit.record(AuditEvent("login", actor="ada"))
    clock.advance(minutes=10)
    store.audit.record(AuditEvent("robot.jog", actor="ada", result="refused"))
    clock.advance(minutes=10)
    store.audit.record(AuditEvent("robot.jog", actor="bob"))
    store.audit.record(AuditEvent("robot.stop", at=t0 + timedelta(hours=1)))
    assert [e.actor for e in store.audit.query(action="robot.jog").entries] == ["bob", "ada"]
    assert [e.action for e in store.audit.query(actor="ada").entries] == ["robot.jog", "login"]
    window = store.audit.query(since=t0 + timedelta(minutes=5), until=t0 + timedelta(minutes=15))
    assert [e.result for e in window.entries] == ["refused"]
    assert store.audit.query(actor="' OR 1=1 --").entries == ()


def test_paging_walks_every_entry_once(store: Store, clock: FakeClock) -> None:
    ids = []
    for i in range(23):
        clock.advance(seconds=1)
        ids.append(store.audit.record(AuditEvent("tick", details={"i": i})))
    seen: list[int] = []
    before = None
    while True:
        page = store.audit.query(limit=10, before=before)
        seen.extend(e.id for e in page.entries)
        # New events arriving between pages do not disturb paging backwards.
        store.audit.record(AuditEvent("late"))
        if page.next_before is None:
            break
        before = page.next_before
    assert seen == sorted(ids, reverse=True)


def test_audit_log_is_append_only(store: Store, db_path: Path) -> None:
    store.audit.record(AuditEvent("login", actor="ada"))
    conn = sqlite3.connect(db_path)
    try:
        with pytest.raises(sqlite3.IntegrityError, match="append-only"):
            conn.execute("UPDATE audit SET actor = 'mallory'")
        with pytest.raises(sqlite3.IntegrityError, match="append-only"):
            conn.execute("DELETE FROM audit")
    finally:
        conn.close()
    with pytest.raises(DatabaseError, match="append-only"):
        store.db.write(lambda c: c.execute("DELETE FROM audit"))
    assert len(store.audit.query().entries) == 1


def test_record_async(store: Store) -> None:
    import asyncio

    event_id = asyncio.run(store.audit.record_async(AuditEvent("robot.stop", actor="tom")))
    assert store.audit.query().entries[0].id == event_id
