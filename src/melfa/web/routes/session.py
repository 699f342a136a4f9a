"""Sign in and out: `POST /api/session` (JSON) and the `/login` form share one path.

Cookies: the session token is HttpOnly, SameSite=Strict, and Secure when the page came
over https; the CSRF token is a readable cookie and is also in the reply body. Each attempt
is admitted and counted before its password is checked (`melfa.store.logins`: per address,
per account, per account from its usual address, with back-off); the hash runs in its own
bounded pool. Signing out, or changing one's password, closes the sockets it ends.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, Form, Request, Response
from fastapi.responses import HTMLResponse, RedirectResponse

from melfa.store import AuditEvent, NewSession, User
from melfa.store.logins import LoginTicket
from melfa.vocab.desk import DeskAction
from melfa.web.config import CSRF_COOKIE, SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.convert import user_out
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import LoginIn, Ok, OwnPasswordIn, SessionOut
from melfa.web.pools import Busy

router = APIRouter(prefix="/api/session", tags=["session"], responses=ERROR_RESPONSES)
pages = APIRouter(include_in_schema=False)

LOGIN_PAGE = Path(__file__).resolve().parent.parent / "static" / "login.html"


def client_addr(request: Request) -> str:
    return request.client.host if request.client is not None else "unknown"


async def password_checked(
    context: WebContext, username: str, password: str, addr: str
) -> User | None:
    """The account if ``password`` is its password, None if not; `ApiError` 429 when this
    account or address has failed too often. Every password check goes through here (the
    sign-in and the current password of a change), so each is counted by the throttle."""
    store = context.store
    ticket = await context.db(store.logins.begin, username, addr)
    if not isinstance(ticket, LoginTicket):
        seconds = ticket.retry_after.total_seconds() if ticket.retry_after else 60.0
        retry = max(1, math.ceil(seconds))
        raise ApiError(
            429,
            "too-many-logins",
            f"{ticket.reason}; wait {retry} s and try again",
            headers={"Retry-After": str(retry)},
            detail={"retry_after_s": retry},
        )
    try:
        user = await context.hash(store.accounts.authenticate, username, password)
    except Busy:
        await context.db(store.logins.cancel, ticket)  # never checked: not a failure
        raise
    await context.db(store.logins.finish, ticket, user is not None)
    return user


async def sign_in(context: WebContext, username: str, password: str, addr: str) -> NewSession:
    """A new session, or `ApiError` 429 (too many failures) / 401 (wrong name or password)."""
    user = await password_checked(context, username, password, addr)
    if user is None:
        raise ApiError(401, "wrong-login", "Wrong username or password")
    new = await context.db(context.store.sessions.create, user, addr)
    context.guard.known.remember(new.token, new.session)  # a first STOP needs no store read
    await context.store.audit.record_async(
        AuditEvent(
            action=DeskAction.SIGN_IN.value,
            actor=user.username,
            role=user.role.value,
            details={"from": addr},
        )
    )
    return new


def set_cookies(request: Request, response: Response, new: NewSession) -> None:
    secure = request.app.state.web.settings.secure_cookies
    if secure is None:
        secure = request.url.scheme == "https"
    age = int((new.session.expires - new.session.created).total_seconds())
    common = {"max_age": age, "path": "/", "secure": secure, "samesite": "strict"}
    response.set_cookie(SESSION_COOKIE, new.token, httponly=True, **common)
    response.set_cookie(CSRF_COOKIE, new.session.csrf_token, httponly=False, **common)


def clear_cookies(response: Response) -> None:
    response.delete_cookie(SESSION_COOKIE, path="/")
    response.delete_cookie(CSRF_COOKIE, path="/")


def check_origin(request: Request) -> None:
    """Login forms only from our own pages (no login CSRF from another site)."""
    origin = request.headers.get("origin")
    if origin is None or origin == "null":
        return
    host = request.headers.get("host", "")
    allowed = request.app.state.web.settings.allowed_origins
    if origin.split("://", 1)[-1] != host and origin not in allowed:
        raise ApiError(403, "bad-origin", f"sign-in from {origin} is not allowed")


@router.post("", response_model=SessionOut, summary="Sign in")
async def login(
    body: LoginIn, request: Request, response: Response, context: ContextDep
) -> SessionOut:
    check_origin(request)
    new = await sign_in(context, body.username, body.password, client_addr(request))
    set_cookies(request, response, new)
    session = new.session
    return SessionOut(
        user=user_out(session.user), csrf_token=session.csrf_token, expires=session.expires
    )


@router.get("", response_model=SessionOut, summary="Who is signed in")
async def whoami(session: SessionDep) -> SessionOut:
    return SessionOut(
        user=user_out(session.user), csrf_token=session.csrf_token, expires=session.expires
    )


@router.delete("", response_model=Ok, summary="Sign out")
async def logout(
    request: Request, response: Response, session: SessionDep, context: ContextDep
) -> Ok:
    await context.db(context.store.sessions.revoke_id, session.id)
    context.guard.revoke_session(session.id, "signed out")
    clear_cookies(response)
    return Ok()


@router.put("/password", response_model=Ok, summary="Change your own password")
async def change_password(
    body: OwnPasswordIn, request: Request, session: SessionDep, context: ContextDep
) -> Ok:
    """Needs the current password (a borrowed, unlocked laptop is not enough); a wrong one
    counts as a failed sign-in (429 after too many, as for signing in). Your other
    sessions end and their sockets close; this one stays signed in. Weak and common
    passwords are refused (422 with the reason)."""
    store = context.store
    user = await password_checked(
        context, session.user.username, body.current, client_addr(request)
    )
    if user is None:
        raise ApiError(403, "wrong-password", "your current password is not right")
    await context.hash(store.accounts.set_password, user.username, body.new, revoke_sessions=False)
    await context.db(store.sessions.revoke_others, user.id, session.id)
    context.guard.revoke_user(user.username, "the password was changed", keep_session=session.id)
    return Ok()


def _login_page(message: str = "", status: int = 200) -> HTMLResponse:
    import html

    page = LOGIN_PAGE.read_text(encoding="utf-8")
    note = f'<p class="error" role="alert">{html.escape(message)}</p>' if message else ""
    return HTMLResponse(page.replace("<!--message-->", note), status_code=status)


def _next(target: str | None) -> str:
    """Only local paths: never redirect off the site."""
    if target and target.startswith("/") and not target.startswith("//"):
        return target
    return "/"


@pages.get("/login")
async def login_page() -> HTMLResponse:
    return _login_page()


@pages.post("/login", response_model=None)
async def login_form(
    request: Request,
    context: ContextDep,
    username: Annotated[str, Form(max_length=200)] = "",
    password: Annotated[str, Form(max_length=1024)] = "",
    next: Annotated[str, Form(max_length=500)] = "/",
) -> Response:
    try:
        check_origin(request)
        new = await sign_in(context, username, password, client_addr(request))
    except ApiError as exc:
        return _login_page(exc.message, exc.status)
    response = RedirectResponse(_next(next), status_code=303)
    set_cookies(request, response, new)
    return response


__all__ = [
    "clear_cookies",
    "client_addr",
    "pages",
    "password_checked",
    "router",
    "set_cookies",
    "sign_in",
]
