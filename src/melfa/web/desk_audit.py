"""What staff do at the instructor's desk, into the audit log: one entry by the signed-in
member of staff, its action one of `melfa.vocab.desk.DeskAction` (the desk's audit view
words it). Every desk route records through `audit_desk`."""

from __future__ import annotations

from melfa.store import AuditEvent, Session
from melfa.vocab.desk import DeskAction
from melfa.web.context import WebContext


async def audit_desk(
    context: WebContext, session: Session, action: DeskAction, **details: object
) -> None:
    """``action`` by ``session``'s user (name and role), with ``details``."""
    await context.store.audit.record_async(
        AuditEvent(
            action=action.value,
            actor=session.user.username,
            role=session.user.role.value,
            details=dict(details),
        )
    )


__all__ = ["audit_desk"]
