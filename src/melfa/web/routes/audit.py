"""The audit log for instructors and admins: JSON with paging and filters (by time, user,
action and robot: one robot's log is its entries). People read it on the instructor's desk
(``/desk#audit``, in local time and plain words); ``/audit`` leads there. Everyone reads
their own entries of a robot's log (``/api/robot/log``: the IDE's *Robot log*)."""

from __future__ import annotations

import datetime as dt
from typing import Annotated

from fastapi import APIRouter, Query
from fastapi.responses import RedirectResponse, Response

from melfa.store import AuditPage
from melfa.vocab.robot_log import LAB_ROBOT, simulator_of
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, SessionDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import AuditEntryOut, AuditPageOut
from melfa.web.target_deps import TARGET_HELP
from melfa.web.targets import LAB, MINE

router = APIRouter(prefix="/api/audit", tags=["audit"], responses=ERROR_RESPONSES)
mine = APIRouter(prefix="/api/robot", tags=["robot"], responses=ERROR_RESPONSES)
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
    limit: int,
    since: dt.datetime | None = None,
    until: dt.datetime | None = None,
    actor: str | None = None,
    action: str | None = None,
    robot: str | None = None,
    before: int | None = None,
) -> AuditPageOut:
    """A page of the audit log, newest first, filtered (`melfa.store.audit.AuditLog.query`)."""
    page: AuditPage = await context.db(
        context.store.audit.query,
        since=_aware(since, "since"),
        until=_aware(until, "until"),
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
    return await query(
        context,
        since=since,
        until=until,
        actor=actor,
        action=action,
        robot=robot,
        limit=limit,
        before=before,
    )


@mine.get("/log", response_model=AuditPageOut, summary="My robot log")
async def my_robot_log(
    session: SessionDep,
    context: ContextDep,
    target: Annotated[str, Query(description=TARGET_HELP)] = LAB,
    limit: Annotated[int, Query(ge=1, le=500)] = 200,
    before: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> AuditPageOut:
    """What I asked this robot to do and what came of it, and control changes I caused,
    newest first, kept on the server (the audit log's entries of mine on that robot): the
    IDE's *Robot log*, the same in every tab and after a reload."""
    user = session.user.username
    if target not in (LAB, MINE):
        raise ApiError(404, "unknown-target", f"no robot {target!r}", where={"field": "target"})
    robot = LAB_ROBOT if target == LAB else simulator_of(user)
    return await query(context, actor=user, robot=robot, limit=limit, before=before)


@pages.get("/audit", response_model=None)
async def audit_page() -> Response:
    """The audit log is read on the instructor's desk, in local time and plain words."""
    return RedirectResponse("/desk#audit", status_code=308)


__all__ = ["mine", "pages", "router"]
