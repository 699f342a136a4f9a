"""The web's side of the queues of the shared robots: one `QueueKeeper` per shared target
(today the lab robot, ``lab``), composed with the store (its stored document, the audit
log) and the open sockets (a student is present while any socket of theirs is open, on
the lab robot or on their own simulator); and the queue as the live protocol's models
(`melfa.live.messages.QueueOut`)."""

from __future__ import annotations

import dataclasses
import logging
from concurrent.futures import Future
from dataclasses import asdict

from melfa.live.messages import QueueMessage, QueueOut, QueueStepOut
from melfa.service import RobotService
from melfa.service.clock import Clock
from melfa.service.queue import QueueSettings, Step
from melfa.service.queue_keeper import QueueChanged, QueueKeeper, QueueView
from melfa.store import Store
from melfa.store.audit import insert_event
from melfa.store.models import AuditEvent
from melfa.web.guard import SocketGuard

_log = logging.getLogger("melfa.web.queues")


def make_keeper(
    target: str,
    service: RobotService,
    store: Store,
    guard: SocketGuard,
    settings: QueueSettings,
    clock: Clock,
) -> QueueKeeper:
    """The keeper of ``target``'s queue, stored and audited in ``store``."""

    def audit(target: str, step: Step) -> None:
        event = AuditEvent(
            action=f"queue.{step.kind.value}",
            actor=step.by or step.user,
            details={
                "target": target,
                "user": step.user,
                "by": step.by,
                "position": step.position,
                "seconds": step.seconds,
                "words": step.words(),
            },
        )
        event = dataclasses.replace(event, at=store.db.clock())
        store.db.submit_write(lambda conn: insert_event(conn, event)).add_done_callback(_report)

    return QueueKeeper(
        target,
        service,
        settings,
        clock=clock,
        storage=store.queues,
        audit=audit,
        present=lambda user: guard.count(user) > 0,
    )


def _report(future: Future[int]) -> None:
    exc = future.exception()
    if exc is not None:
        _log.error("a queue audit entry was not written: %s", exc)


def queue_out(view: QueueView) -> QueueOut:
    """The queue as ``GET /api/queue`` and the live message give it."""
    return QueueOut.model_validate(asdict(view))


def queue_message(view: QueueView, steps: tuple[Step, ...] = ()) -> QueueMessage:
    data = asdict(view)
    data["steps"] = [
        QueueStepOut(
            kind=s.kind, user=s.user, by=s.by, position=s.position, seconds=s.seconds
        ).model_dump()
        for s in steps
    ]
    return QueueMessage.model_validate(data)


def message_of_change(event: QueueChanged) -> QueueMessage:
    return queue_message(event.view, event.steps)


__all__ = ["make_keeper", "message_of_change", "queue_message", "queue_out"]
