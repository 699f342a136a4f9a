"""Dependencies declared once (the FastAPI template's api/deps.py): the context, the
signed-in session with CSRF checked on every state-changing request, the service `Actor`,
and role gates.

Every dependency here is ``async``: FastAPI runs a plain ``def`` dependency in the thread
pool every request shares, one more hop away from the event loop and back (on two busy
cores each hop waits for the CPU again); these do nothing that blocks."""

from __future__ import annotations

import contextlib
from collections.abc import Awaitable, Callable
from typing import Annotated

from fastapi import BackgroundTasks, Depends, Request, WebSocket
from starlette.requests import HTTPConnection

from melfa.service import Actor
from melfa.service import Role as ServiceRole
from melfa.service.lab_network import Address, peer_address
from melfa.store import Role, Session, check_csrf, is_access_token
from melfa.web.config import CSRF_HEADER, SAFE_METHODS, SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.errors import ApiError


async def get_context(request: Request) -> WebContext:
    context: WebContext = request.app.state.web
    return context


def ws_context(websocket: WebSocket) -> WebContext:
    context: WebContext = websocket.app.state.web
    return context


ContextDep = Annotated[WebContext, Depends(get_context)]


async def find_session(context: WebContext, token: str | None) -> Session | None:
    """The live session for a cookie token or a personal access token
    (`melfa.store.tokens`), or None."""
    if not token:
        return None
    if is_access_token(token):
        return await context.db(context.store.tokens.lookup, token)
    return await context.db(context.store.sessions.lookup, token)


def bearer_token(request: Request) -> str | None:
    """The token of an ``Authorization: Bearer <token>`` header, if any."""
    kind, _, value = request.headers.get("authorization", "").partition(" ")
    return value.strip() or None if kind.lower() == "bearer" else None


async def _signed_in(
    request: Request, context: WebContext, find: Callable[[str], Awaitable[Session | None]]
) -> Session:
    """The signed-in session found with ``find``; 401 without one, 403 when a
    state-changing request lacks the session's CSRF token in `X-CSRF-Token`."""
    bearer = bearer_token(request)
    if bearer is not None:
        # A personal access token: sent by a program, never by a browser on its own, so
        # no CSRF token is needed (only tokens, not session cookies, are taken here).
        session = await find(bearer) if is_access_token(bearer) else None
        if session is None:
            raise ApiError(401, "bad-token", "the Bearer token is unknown or revoked")
        request.state.user = session.user.username
        return session
    token = request.cookies.get(SESSION_COOKIE)
    session = await find(token) if token else None
    if session is None:
        raise ApiError(401, "not-signed-in", "sign in first (POST /api/session)")
    request.state.user = session.user.username
    if request.method not in SAFE_METHODS and not check_csrf(
        session, request.headers.get(CSRF_HEADER)
    ):
        raise ApiError(
            403,
            "csrf-token-missing",
            f"this request changes something, so it needs the {CSRF_HEADER} header with "
            "the session's CSRF token (from the login reply or the melfa_csrf cookie)",
        )
    return session


async def get_session(request: Request, context: ContextDep) -> Session:
    """The signed-in session (see `_signed_in`), looked up in the store's pool; a session
    found is remembered for STOP (`get_stop_session`)."""

    async def find(token: str) -> Session | None:
        session = await find_session(context, token)
        if session is not None:
            context.guard.known.remember(token, session)
        return session

    return await _signed_in(request, context, find)


async def stop_lookup(context: WebContext, token: str) -> Session | None:
    """A STOP's session read from the store, read-only, in a pool nothing else uses (no
    login flood, check or store write delays it), and remembered (or forgotten)."""
    if is_access_token(token):
        session = await context.pools.stop.run(context.store.tokens.lookup, token)
    else:
        session = await context.pools.stop.run(context.store.sessions.lookup, token, touch=False)
    known = context.guard.known
    if session is None:
        known.forget(token)
    else:
        known.remember(token, session)
    return session


async def reconfirm(context: WebContext, token: str) -> None:
    """Read a remembered session again (after the STOP that used it was answered). Best
    effort: when it cannot be read (the pool full, the server closing), the entry ages out
    after `Limits.stop_session_memory_s`; the STOP's reply has gone, nothing to report."""
    with contextlib.suppress(Exception):
        await stop_lookup(context, token)


async def get_stop_session(
    request: Request, context: ContextDep, after: BackgroundTasks
) -> Session:
    """The session of a STOP: from memory when this server confirmed it recently
    (`melfa.web.known_sessions`: no thread, no store; read again once the STOP is
    answered when it is older than `Limits.socket_recheck_s`), else `stop_lookup`."""

    async def find(token: str) -> Session | None:
        recalled = context.guard.known.recall(token)
        if recalled is None:
            return await stop_lookup(context, token)
        if recalled.stale:
            after.add_task(reconfirm, context, token)
        return recalled.session

    return await _signed_in(request, context, find)


SessionDep = Annotated[Session, Depends(get_session)]
StopSessionDep = Annotated[Session, Depends(get_stop_session)]


def service_role(role: Role) -> ServiceRole:
    """Admins and instructors are instructors to the robot (they may take over)."""
    return ServiceRole.STUDENT if role is Role.STUDENT else ServiceRole.INSTRUCTOR


def peer_of(connection: HTTPConnection) -> Address:
    """Where a request or socket comes from: its peer's address (behind a reverse proxy
    given with ``--trusted-proxy``, uvicorn has put the client's own there)."""
    client = connection.client
    return peer_address(client.host if client is not None else None)


def actor_of(session: Session, address: Address | None = None) -> Actor:
    """The service's view of a web session (the session id is a hash: safe to show), from
    ``address`` (`peer_of`; the lab's networks ask it)."""
    return Actor(session.user.username, service_role(session.user.role), session.id[:16], address)


async def get_actor(request: Request, session: SessionDep) -> Actor:
    return actor_of(session, peer_of(request))


ActorDep = Annotated[Actor, Depends(get_actor)]


async def require_staff(session: SessionDep) -> Session:
    if not session.user.role.is_staff:
        raise ApiError(403, "forbidden", "only instructors and admins may do this")
    return session


async def require_admin(session: SessionDep) -> Session:
    if session.user.role is not Role.ADMIN:
        raise ApiError(403, "forbidden", "only admins may manage accounts")
    return session


StaffDep = Annotated[Session, Depends(require_staff)]
AdminDep = Annotated[Session, Depends(require_admin)]

__all__ = [
    "ActorDep",
    "AdminDep",
    "ContextDep",
    "SessionDep",
    "StaffDep",
    "StopSessionDep",
    "actor_of",
    "bearer_token",
    "find_session",
    "get_context",
    "peer_of",
    "service_role",
    "ws_context",
]
