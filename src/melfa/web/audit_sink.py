"""The store as the service's audit sink (`melfa.service.audit.AuditSink`).

It lives in the web layer, which composes the two: the store knows nothing of the service.

The service calls ``write(entry)`` on its event loop and asks that it neither block nor
raise; so the entry is converted at once and queued on the store's writer thread without
waiting. A failed write is logged (``melfa.store`` logger), never raised into the service.
`flush()` waits for queued entries (shutdown, tests).
"""

from __future__ import annotations

import logging
from concurrent.futures import Future

from melfa.service.events import AuditEvent as ServiceAuditEvent
from melfa.store.audit import AuditLog, insert_event
from melfa.store.models import AuditEvent

__all__ = ["ServiceAuditSink", "from_service_event"]

_log = logging.getLogger("melfa.store")


def from_service_event(entry: ServiceAuditEvent) -> AuditEvent:
    """One service audit entry as a stored event: action ``robot.<command>``."""
    actor = entry.actor
    return AuditEvent(
        action=f"robot.{entry.command}",
        actor=None if actor is None else actor.user,
        role=None if actor is None else actor.role.value,
        details={
            "command_id": entry.command_id,
            "detail": entry.detail,
            "moves": entry.moves,
            "session": None if actor is None else actor.session_id,
        },
        result=entry.result,
        at=entry.at,
    )


class ServiceAuditSink:
    """Adapter: ``RobotService(audit=ServiceAuditSink(store.audit))``."""

    def __init__(self, audit: AuditLog) -> None:
        self.audit = audit

    def write(self, entry: ServiceAuditEvent) -> None:
        try:
            event = from_service_event(entry)
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
