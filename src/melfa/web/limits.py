"""Limits on every input, and the headers every page carries (docs/security.md).

`Limits` holds every number (each a documented setting); `Shield` is the outermost ASGI
middleware: it refuses a body larger than its route allows with 413 before reading more
(by Content-Length, or by counting a chunked body), refuses a Host not in the allow-list
(DNS rebinding), refuses a cross-site or ``null`` Origin on anything that changes state,
caps the requests one client runs at once, and adds the security headers (CSP with
frame-ancestors, nosniff, no referrer leaks) to every response.
"""

from __future__ import annotations

import base64
import hashlib
import json
import re
import time
from collections.abc import Awaitable, Callable, MutableMapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from starlette.exceptions import HTTPException

from melfa.ros.rosapi import PARAM_BYTES, PARAM_BYTES_TOTAL

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]

KIB = 1024
MIB = 1024 * KIB

SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


@dataclass(frozen=True)
class Limits:
    """Every limit of the web server, with its default (`WebSettings.limits`)."""

    body_bytes: int = 64 * KIB
    """Largest request body on routes not listed in ``body_bytes_by_route``."""
    body_bytes_by_route: tuple[tuple[str, int], ...] = (
        ("/api/session", 8 * KIB),
        ("/login", 8 * KIB),
        ("/api/workspaces", 4 * MIB),
        ("/api/check", 4 * MIB),
        ("/api/number", 4 * MIB),
        ("/api/strip", 4 * MIB),
        ("/api/robot", 4 * MIB),
        ("/api/debug", 4 * MIB),
    )
    """(path prefix, bytes): a program and its points are up to 1,000,000 characters each."""
    header_bytes: int = 16 * KIB
    """Largest request line plus headers (uvicorn ``h11_max_incomplete_event_size``)."""
    header_timeout_s: float = 10.0
    """A connection that has not sent its whole first request head by then is closed."""
    keep_alive_s: float = 5.0
    """An idle kept-alive HTTP connection is closed after this long."""
    max_connections: int = 400
    """Open connections to the server overall; beyond, 503 (uvicorn ``limit_concurrency``).
    Connections still waiting for their first request head are not counted (they are
    closed after ``header_timeout_s``): slow heads cannot take every place."""
    max_requests_per_client: int = 16
    """HTTP requests one session (or, signed out, one address) runs at once; beyond, 429."""
    max_sockets_per_user: int = 8
    """Open /api/ws and /rosbridge sockets per user."""
    max_sockets: int = 200
    """Open sockets overall, those still signing in counted."""
    max_sockets_signing_in: int = 32
    """/rosbridge sockets open but not yet signed in (they have 10 s for their ``auth``);
    beyond, refused before the handshake."""
    rosapi_param_chars: int = PARAM_BYTES
    """Characters of rosapi parameter values (``set_param``) one /rosbridge socket holds."""
    rosapi_param_chars_total: int = PARAM_BYTES_TOTAL
    """Characters of rosapi parameter values all sockets together hold."""
    ws_message_bytes: int = 1 * MIB
    """Largest WebSocket message the server reads at all (rosbridge may carry a program);
    /api/ws messages are further limited to 4096 characters."""
    ws_messages_per_s: float = 60.0
    """Sustained messages per second on one socket (heartbeats are 10/s)."""
    ws_burst: int = 120
    """Messages allowed in a burst above that rate; beyond, the socket is closed (1008)."""
    json_depth: int = 32
    """Deepest nesting of a JSON message on a socket."""
    socket_recheck_s: float = 2.0
    """How often an open socket's session is re-read (changes made by another process);
    a STOP answered from a session in memory older than this re-reads it once answered."""
    stop_session_memory_s: float = 60.0
    """A STOP is answered from a session this server confirmed within this long, without
    reading the store (`melfa.web.known_sessions`); older, it is read again."""

    def body_limit(self, path: str) -> int:
        for prefix, limit in self.body_bytes_by_route:
            if path == prefix or path.startswith((prefix + "/", prefix + "?")):
                return limit
        return self.body_bytes


@dataclass
class RateMeter:
    """A token bucket: ``allow()`` is False once a client exceeds rate plus burst."""

    rate: float
    burst: int
    clock: Callable[[], float] = time.monotonic
    tokens: float = field(init=False)
    last: float = field(init=False)

    def __post_init__(self) -> None:
        self.tokens = float(self.burst)
        self.last = self.clock()

    def allow(self) -> bool:
        now = self.clock()
        self.tokens = min(float(self.burst), self.tokens + (now - self.last) * self.rate)
        self.last = now
        if self.tokens < 1:
            return False
        self.tokens -= 1
        return True


_TOKENS = re.compile(r'"(?:[^"\\]|\\.)*"?|[\[\]{}]', re.S)


def json_too_deep(text: str, limit: int) -> bool:
    """Whether ``text`` nests arrays/objects deeper than ``limit`` (strings skipped), so a
    10,000-deep message is refused before the parser recurses.

    >>> json_too_deep('{"a": [[1]]}', 3), json_too_deep('{"a": [[1]]}', 2)
    (False, True)
    >>> json_too_deep('["[[[[\\"", 1]', 1)
    False
    """
    depth = 0
    for match in _TOKENS.finditer(text):
        ch = match.group()[0]
        if ch in "[{":
            depth += 1
            if depth > limit:
                return True
        elif ch in "]}":
            depth -= 1
    return False


def host_allowed(host_header: str, allowed: tuple[str, ...]) -> bool:
    """Host without its port is one of ``allowed`` (none configured: any)."""
    if not allowed:
        return True
    host = host_header.strip().lower()
    if host.startswith("["):
        host = host[1 : host.find("]")] if "]" in host else host
    elif host.count(":") == 1:
        host = host.split(":", 1)[0]
    return host in allowed or "*" in allowed


def origin_allowed(origin: str | None, host: str, allowed: tuple[str, ...]) -> bool:
    """A request's Origin is this site or configured; absent is fine (not a browser);
    ``null`` (sandboxed frames, file: pages) never is. The one rule for forms and sockets."""
    if origin is None:
        return True
    if origin == "null":
        return False
    return origin.split("://", 1)[-1] == host or origin in allowed


def csp_for(page: Path) -> str:
    """The Content-Security-Policy: our own scripts only (the page's inline import map by
    its hash), no framing by other sites, no plugins."""
    hashes = []
    with_inline = re.compile(r"<script(?![^>]*\bsrc=)[^>]*>(.*?)</script>", re.S)
    if page.is_file():
        for body in with_inline.findall(page.read_text(encoding="utf-8")):
            digest = hashlib.sha256(body.encode("utf-8")).digest()
            hashes.append(f"'sha256-{base64.b64encode(digest).decode()}'")
    scripts = " ".join(["'self'", *hashes])
    return (
        f"default-src 'self'; script-src {scripts}; style-src 'self' 'unsafe-inline'; "
        "img-src 'self' data: blob:; font-src 'self' data:; connect-src 'self'; "
        "worker-src 'self' blob:; object-src 'none'; base-uri 'self'; "
        "form-action 'self'; frame-ancestors 'none'"
    )


class Shield:
    """The outermost middleware (see the module docstring)."""

    def __init__(
        self,
        app: ASGIApp,
        *,
        limits: Limits,
        allowed_hosts: tuple[str, ...],
        allowed_origins: tuple[str, ...],
        csp: str,
        session_cookie: str,
    ) -> None:
        self.app = app
        self.limits = limits
        self.allowed_hosts = tuple(h.lower() for h in allowed_hosts)
        self.allowed_origins = allowed_origins
        self.cookie = session_cookie.encode()
        self.in_flight: dict[str, int] = {}
        self.refused: dict[int, int] = {}
        self.headers = [
            (b"content-security-policy", csp.encode()),
            (b"x-content-type-options", b"nosniff"),
            (b"x-frame-options", b"DENY"),
            (b"referrer-policy", b"same-origin"),
            (b"cross-origin-opener-policy", b"same-origin"),
        ]

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        host = headers.get("host", "")
        if not host_allowed(host, self.allowed_hosts):
            await self._refuse(scope, send, 421, "bad-host", f"unknown host {host[:80]!r}")
            return
        if scope["type"] == "websocket":
            await self.app(scope, receive, send)  # sockets check Origin and sessions
            return
        method = scope["method"]
        if method not in SAFE_METHODS and not origin_allowed(
            headers.get("origin"), host, self.allowed_origins
        ):
            origin = headers.get("origin", "")[:80]
            await self._refuse(scope, send, 403, "bad-origin", f"requests from {origin} refused")
            return
        limit = self.limits.body_limit(scope["path"])
        length = headers.get("content-length")
        if length is not None and (not length.isdigit() or int(length) > limit):
            await self._refuse(
                scope, send, 413, "too-large", f"the body is larger than {limit} bytes"
            )
            return
        key = self._client_key(scope, headers)
        if self.in_flight.get(key, 0) >= self.limits.max_requests_per_client:
            await self._refuse(
                scope, send, 429, "too-many-requests", "too many requests at once; wait"
            )
            return
        self.in_flight[key] = self.in_flight.get(key, 0) + 1
        try:
            await self.app(scope, self._counting(receive, limit), self._with_headers(send))
        finally:
            left = self.in_flight[key] - 1
            if left:
                self.in_flight[key] = left
            else:
                del self.in_flight[key]

    def _client_key(self, scope: Scope, headers: dict[str, str]) -> str:
        auth = headers.get("authorization")
        if auth:
            return "a:" + hashlib.sha256(auth.encode()).hexdigest()[:16]
        for part in headers.get("cookie", "").split(";"):
            name, _, value = part.strip().partition("=")
            if name.encode() == self.cookie and value:
                return "c:" + hashlib.sha256(value.encode()).hexdigest()[:16]
        client = scope.get("client")
        return "h:" + (client[0] if client else "?")

    def _counting(self, receive: Receive, limit: int) -> Receive:
        seen = 0

        async def counted() -> Message:
            nonlocal seen
            message = await receive()
            if message["type"] == "http.request":
                seen += len(message.get("body", b""))
                if seen > limit:
                    raise HTTPException(413, f"the body is larger than {limit} bytes")
            return message

        return counted

    def _with_headers(self, send: Send) -> Send:
        async def sending(message: Message) -> None:
            if message["type"] == "http.response.start":
                present = {k.lower() for k, _ in message.get("headers", [])}
                extra = [(k, v) for k, v in self.headers if k not in present]
                message["headers"] = [*message.get("headers", []), *extra]
            await send(message)

        return sending

    async def _refuse(self, scope: Scope, send: Send, status: int, code: str, text: str) -> None:
        self.refused[status] = self.refused.get(status, 0) + 1
        if scope["type"] == "websocket":
            await send({"type": "websocket.close", "code": 1008, "reason": text[:120]})
            return
        error = {"code": code, "message": text, "status": status, "where": None, "detail": None}
        body = json.dumps({"error": error}).encode()
        await send(
            {
                "type": "http.response.start",
                "status": status,
                "headers": [
                    (b"content-type", b"application/json"),
                    (b"content-length", str(len(body)).encode()),
                    (b"connection", b"close"),
                    *self.headers,
                ],
            }
        )
        await send({"type": "http.response.body", "body": body})


__all__ = [
    "Limits",
    "RateMeter",
    "Shield",
    "csp_for",
    "host_allowed",
    "json_too_deep",
    "origin_allowed",
]
