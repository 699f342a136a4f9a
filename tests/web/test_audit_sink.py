"""The web layer's adapter storing the service's audit entries in the store."""

from __future__ import annotations

from pathlib import Path

from melfa.service.audit import AuditSink
from melfa.service.events import Actor
from melfa.service.events import AuditEvent as ServiceEvent
from melfa.service.events import Role as ServiceRole
from melfa.store import Store
from melfa.web.audit_sink import ServiceAuditSink


def test_service_audit_events_are_stored_through_the_sink(tmp_path: Path) -> None:
    with Store(tmp_path / "melfa.sqlite3") as store:
        _check(store)


def _check(store: Store) -> None:
    sink = ServiceAuditSink(store.audit)
    assert isinstance(sink, AuditSink)
    actor = Actor("ada", ServiceRole.STUDENT, "s-1")
    sink.write(ServiceEvent(actor=actor, command_id=7, command="run", detail="slot 1"))
    sink.write(ServiceEvent(actor=actor, command_id=7, command="run", result="ok"))
    sink.flush()
    entries = store.audit.query(actor="ada").entries
    assert [(e.action, e.result) for e in entries] == [
        ("robot.run", "ok"),
        ("robot.run", "accepted"),
    ]
    assert entries[1].details == {
        "command_id": 7,
        "detail": "slot 1",
        "moves": True,
        "session": "s-1",
    }
    assert entries[1].role == "student"
