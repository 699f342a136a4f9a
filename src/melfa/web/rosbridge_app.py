"""rosbridge in the web server: at ``/rosbridge`` of the web port, and on a port of its own
(``melfa serve --rosbridge-port 9090``, where ``rosbridge_server`` listened) for clients
such as the thesis's page that connect to ``ws://host:port`` (docs/ros.md).

Both share the web app's store and robot service; the port's app has only the rosbridge
WebSocket (at ``/`` and ``/rosbridge``) and no cookies of its own to ride on."""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Iterable

from fastapi import APIRouter, FastAPI, WebSocket

from melfa.ros.rosbridge_server import rosbridge_router
from melfa.service.thesis import dialect_named
from melfa.store import Session
from melfa.web.context import WebContext
from melfa.web.deps import actor_of, find_session
from melfa.web.guard import MessageGate, TooManySockets


def rosbridge_routes(
    context_of: FastAPI | None = None, paths: Iterable[str] = ("/rosbridge",)
) -> APIRouter:
    """The rosbridge router; ``context_of``: the app whose state holds the `WebContext`
    (None: the app serving the socket)."""

    def context(websocket: WebSocket) -> WebContext:
        app = context_of if context_of is not None else websocket.app
        web: WebContext = app.state.web
        return web

    async def session_of(websocket: WebSocket, token: str) -> Session | None:
        return await find_session(context(websocket), token)

    async def gate(
        websocket: WebSocket, token: str, end: Callable[[str], Awaitable[None]]
    ) -> MessageGate | None:
        web = context(websocket)
        session = await find_session(web, token)
        if session is None:
            return None
        try:
            handle = web.guard.open(session, token, end, kind="rosbridge")
        except TooManySockets:
            return None
        return MessageGate(web.guard, handle, web.settings.limits)

    mode = "melfa"
    if context_of is not None:
        mode = getattr(context_of.state, "rosbridge_mode", "melfa")
    return rosbridge_router(
        lambda ws: context(ws).service,
        session_of,
        actor_of,
        paths=tuple(paths),
        allowed_origins=lambda ws: context(ws).settings.allowed_origins,
        mode=dialect_named(mode),
        gate=gate,
        admit=lambda ws: context(ws).guard.before_sign_in(),
        params=lambda ws: context(ws).rosapi_params,
    )


def create_rosbridge_app(web_app: FastAPI, mode: str = "melfa") -> FastAPI:
    """The app for the rosbridge port: the WebSocket at ``/`` and ``/rosbridge``, using
    ``web_app``'s store and service (start ``web_app`` first: its lifespan makes them)."""
    dialect_named(mode)  # a bad mode fails here, before anything listens
    web_app.state.rosbridge_mode = mode
    app = FastAPI(title="melfa rosbridge", docs_url=None, redoc_url=None, openapi_url=None)
    app.include_router(rosbridge_routes(web_app, paths=("/", "/rosbridge")))
    return app


__all__ = ["create_rosbridge_app", "rosbridge_routes"]
