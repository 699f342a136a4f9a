"""The audit log for instructors and admins: JSON with paging and filters, and a plain
server-rendered page (`/audit`) for reading it in a browser."""

from __future__ import annotations

import datetime as dt
import html
import json
from typing import Annotated
from urllib.parse import urlencode

from fastapi import APIRouter, Query, Request
from fastapi.responses import HTMLResponse, RedirectResponse, Response

from melfa.store import AuditPage, Role
from melfa.web.config import SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, StaffDep, find_session
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
) -> AuditPage:
    return await context.db(
        context.store.audit.query,
        since=_aware(since, "since"),
        until=_aware(until, "until"),
        actor=actor,
        action=action,
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
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    before: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> AuditPageOut:
    """Filter by time range [since, until), user (``actor``) and ``action`` (robot commands
    are ``robot.<command>``); page with ``before`` = the previous page's ``next_before``."""
    page = await query(
        context,
        since=since,
        until=until,
        actor=actor,
        action=action,
        limit=limit,
        before=before,
    )
    return AuditPageOut(
        entries=[AuditEntryOut.model_validate(e, from_attributes=True) for e in page.entries],
        next_before=page.next_before,
    )


_PAGE = """<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>melfa · audit log</title>
<style>body{{font:14px system-ui,sans-serif;margin:1.5em}}table{{border-collapse:collapse}}
td,th{{border-bottom:1px solid #ddd;padding:.25em .6em;text-align:left;vertical-align:top}}
code{{font-size:12px}}</style></head><body>
<h1>Audit log</h1>
<form method="get">user <input name="actor" value="{actor}"> action
<input name="action" value="{action}"> <button>filter</button></form>
<table><thead><tr><th>#</th><th>time (UTC)</th><th>user</th><th>role</th><th>action</th>
<th>result</th><th>details</th></tr></thead><tbody>
{rows}
</tbody></table>
<p>{more}</p>
</body></html>
"""


@pages.get("/audit", response_model=None)
async def audit_page(
    request: Request,
    actor: Annotated[str | None, Query(max_length=200)] = None,
    action: Annotated[str | None, Query(max_length=200)] = None,
    before: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> Response:
    context: WebContext = request.app.state.web
    session = await find_session(context, request.cookies.get(SESSION_COOKIE))
    if session is None:
        return RedirectResponse("/login?next=/audit", status_code=303)
    if session.user.role is Role.STUDENT:
        return HTMLResponse("<p>Only instructors and admins may read the audit log.</p>", 403)
    request.state.user = session.user.username
    page = await query(
        context,
        since=None,
        until=None,
        actor=actor or None,
        action=action or None,
        limit=100,
        before=before,
    )
    e = html.escape
    rows = "\n".join(
        f"<tr><td>{x.id}</td><td>{e(x.at.strftime('%Y-%m-%d %H:%M:%S'))}</td>"
        f"<td>{e(x.actor or '—')}</td><td>{e(x.role or '')}</td><td>{e(x.action)}</td>"
        f"<td>{e(x.result)}</td><td><code>{e(json.dumps(x.details, sort_keys=True))}</code></td>"
        "</tr>"
        for x in page.entries
    )
    more = ""
    if page.next_before is not None:
        params = {k: v for k, v in (("actor", actor), ("action", action)) if v}
        params["before"] = str(page.next_before)
        more = f'<a href="/audit?{e(urlencode(params))}">older entries</a>'
    body = _PAGE.format(actor=e(actor or ""), action=e(action or ""), rows=rows, more=more)
    return HTMLResponse(body)


__all__ = ["pages", "router"]
