"""The web layer's adapter storing the service's audit entries in the store."""

from __future__ import annotations

import ipaddress
from pathlib import Path

from melfa.service.audit import AuditSink
from melfa.service.events import Actor, RobotNote
from melfa.service.events import AuditEvent as ServiceEvent
from melfa.service.events import Role as ServiceRole
from melfa.store import Store
from melfa.vocab.robot_log import NoteKind
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
        "robot": "lab",
    }
    assert entries[1].role == "student"
    # Over the network: where from (the lab's networks ask it), for the instructor.
    away = Actor("ada", ServiceRole.STUDENT, "s-1", ipaddress.ip_address("84.12.3.4"))
    sink.write(ServiceEvent(actor=away, command_id=8, command="run", result="refused: …"))
    sink.flush()
    assert store.audit.query(actor="ada").entries[0].details["address"] == "84.12.3.4"


def test_each_robot_s_notes_are_its_log(tmp_path: Path) -> None:
    """A note (control, alarm) is stored under its robot: one robot's log is a query."""
    with Store(tmp_path / "melfa.sqlite3") as store:
        ada = Actor("ada", ServiceRole.STUDENT, "s-1")
        lab, mine = ServiceAuditSink(store.audit), ServiceAuditSink(store.audit, "sim:ada")
        lab.note(RobotNote(actor=ada, kind=NoteKind.CONTROL, facts={"reason": "acquired"}))
        mine.note(RobotNote(actor=ada, kind=NoteKind.ALARM, facts={"number": 9100}))
        mine.write(ServiceEvent(actor=ada, command_id=1, command="run"))
        lab.flush()
        assert [e.action for e in store.audit.query(robot="lab").entries] == ["control.changed"]
        log = store.audit.query(robot="sim:ada").entries
        assert [(e.action, e.details.get("number")) for e in log] == [
            ("robot.run", None),
            ("alarm.raised", 9100),
        ]
