"""The store as the service's audit sink (`melfa.service.audit.AuditSink`).

It lives in the web layer, which composes the two: the store knows nothing of the service.

Each robot has its own sink, named by ``robot`` (`melfa.vocab.robot_log`: ``lab``, or
``sim:<user>`` for a private simulator), kept in every entry's ``details.robot``: the
desk's robot log of one robot is the audit's entries of that robot.

The service calls ``write(entry)`` and ``note(entry)`` on its event loop and asks that
neither block nor raise; so the entry is converted at once and queued on the store's writer
thread without waiting. A failed write is logged (``melfa.store`` logger), never raised into
the service. `flush()` waits for queued entries (shutdown, tests).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import Future

from melfa.service.events import AuditEvent as ServiceAuditEvent
from melfa.service.events import RobotNote
from melfa.store.audit import AuditLog, insert_event
from melfa.store.models import AuditEvent
from melfa.vocab.robot_log import LAB_ROBOT

__all__ = ["ServiceAuditSink", "from_note", "from_service_event"]

_log = logging.getLogger("melfa.store")


def from_service_event(entry: ServiceAuditEvent, robot: str = LAB_ROBOT) -> AuditEvent:
    """One service audit entry as a stored event: action ``robot.<command>``, with the
    address it came from when it came over the network."""
    actor = entry.actor
    details: dict[str, object] = {
        "command_id": entry.command_id,
        "detail": entry.detail,
        "moves": entry.moves,
        "session": None if actor is None else actor.session_id,
        "robot": robot,
    }
    if actor is not None and actor.address is not None:
        details["address"] = str(actor.address)  # where from (the lab's networks ask it)
    return AuditEvent(
        action=f"robot.{entry.command}",
        actor=None if actor is None else actor.user,
        role=None if actor is None else actor.role.value,
        details=details,
        result=entry.result,
        at=entry.at,
    )


def from_note(entry: RobotNote, robot: str = LAB_ROBOT) -> AuditEvent:
    """One robot note as a stored event: action the note's kind (``control.changed``…)."""
    actor = entry.actor
    return AuditEvent(
        action=entry.kind.value,
        actor=None if actor is None else actor.user,
        role=None if actor is None else actor.role.value,
        details={**entry.facts, "robot": robot},
        result="",
        at=entry.at,
    )


class ServiceAuditSink:
    """Adapter: ``RobotService(audit=ServiceAuditSink(store.audit, robot))``."""

    def __init__(self, audit: AuditLog, robot: str = LAB_ROBOT) -> None:
        self.audit = audit
        self.robot = robot

    def write(self, entry: ServiceAuditEvent) -> None:
        self._queue(lambda: from_service_event(entry, self.robot), entry)

    def note(self, entry: RobotNote) -> None:
        self._queue(lambda: from_note(entry, self.robot), entry)

    def _queue(self, convert: Callable[[], AuditEvent], entry: object) -> None:
        try:
            event = convert()
            future = self.audit.db.submit_write(lambda conn: insert_event(conn, event))
        except Exception:
            _log.exception("audit entry could not be queued: %r", entry)
            return
        future.add_done_callback(_report)

    def flush(self) -> None:
        self.audit.db.flush()


def _report(future: Future[int]) -> None:
    error = future.exception()
    if error is not None:
        _log.error("audit entry was not stored: %s", error)
