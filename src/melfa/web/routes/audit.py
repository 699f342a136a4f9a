"""The audit log for instructors and admins: JSON with paging and filters (by time, user,
action and robot: one robot's log is its entries). People read it on the instructor's desk
(``/desk#audit``, in local time and plain words); ``/audit`` leads there."""

from __future__ import annotations

import datetime as dt
from typing import Annotated

from fastapi import APIRouter, Query
from fastapi.responses import RedirectResponse, Response

from melfa.store import AuditPage
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import AuditEntryOut, AuditPageOut

router = APIRouter(prefix="/api/audit", tags=["audit"], responses=ERROR_RESPONSES)
pages = APIRouter(include_in_schema=False)


def _aware(moment: dt.datetime | None, name: str) -> dt.datetime | None:
    """Times without a zone are UTC; an unrepresentable one is the caller's mistake."""
    if moment is None:
        return None
    if moment.tzinfo is None:
        moment = moment.replace(tzinfo=dt.UTC)
    try:
        return moment.astimezone(dt.UTC)
    except (OverflowError, ValueError):
        raise ApiError(
            422, "invalid-value", f"{name}: time out of range", where={"field": name}
        ) from None


async def query(
    context: WebContext,
    *,
    since: dt.datetime | None,
    until: dt.datetime | None,
    actor: str | None,
    action: str | None,
    limit: int,
    before: int | None,
    robot: str | None = None,
) -> AuditPage:
    return await context.db(
        context.store.audit.query,
        since=_aware(since, "since"),
        until=_aware(until, "until"),
        actor=actor,
        action=action,
        robot=robot,
        limit=limit,
        before=before,
    )


@router.get("", response_model=AuditPageOut, summary="Audit entries, newest first")
async def list_audit(
    session: StaffDep,
    context: ContextDep,
    since: dt.datetime | None = None,
    until: dt.datetime | None = None,
    actor: Annotated[str | None, Query(max_length=200)] = None,
    action: Annotated[str | None, Query(max_length=200)] = None,
    robot: Annotated[str | None, Query(max_length=200)] = None,
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    before: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> AuditPageOut:
    """Filter by time range [since, until), user (``actor``), ``action`` (robot commands
    are ``robot.<command>``; control changes, alarms and the link ``control.changed``,
    ``alarm.raised``, ``alarm.cleared``, ``link.changed``) and ``robot`` (``lab``, or
    ``sim:<user>``: that robot's log); page with ``before`` = the previous page's
    ``next_before``."""
    page = await query(
        context,
        since=since,
        until=until,
        actor=actor,
        action=action,
        robot=robot,
        limit=limit,
        before=before,
    )
    return AuditPageOut(
        entries=[AuditEntryOut.model_validate(e, from_attributes=True) for e in page.entries],
        next_before=page.next_before,
    )


@pages.get("/audit", response_model=None)
async def audit_page() -> Response:
    """The audit log is read on the instructor's desk, in local time and plain words."""
    return RedirectResponse("/desk#audit", status_code=308)


__all__ = ["pages", "router"]
