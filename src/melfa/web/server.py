"""Running the app under uvicorn with the limits that live at the connection level: the
time allowed for a request head, the size of a head, keep-alive, the number of open
connections, the largest WebSocket message, and which proxies' headers are believed.
`melfa serve`, the tests and the benchmarks all start the server through `uvicorn_config`.
"""

from __future__ import annotations

import asyncio
from typing import Any, ClassVar

import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

from melfa.web.limits import Limits


def header_timeout_protocol(seconds: float) -> type[H11Protocol]:
    """uvicorn's h11 protocol, closing a connection whose first request head has not
    arrived within ``seconds`` (slow-header attacks: uvicorn itself waits forever).

    Connections still waiting for their first head do not count towards the connection
    limit (``limit_concurrency``, 503 beyond): an attacker who reopens each connection as
    soon as it is cut would otherwise hold every place under the limit, and everyone
    else would get 503. (Closing the oldest waiting ones instead makes such an attacker
    reconnect in a tight loop that eats the event loop.)"""

    class HeaderTimeoutH11(H11Protocol):
        slow_closed = 0
        """Connections closed for a head that did not come in time."""
        waiting: ClassVar[dict[HeaderTimeoutH11, None]] = {}
        """Connections waiting for their first head."""

        def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self._limit = self.limit_concurrency
            self._head_timer: asyncio.TimerHandle | None = self.loop.call_later(
                seconds, self._head_too_slow
            )
            type(self).waiting[self] = None

        def handle_events(self) -> None:
            if self._limit is not None:
                others = len(type(self).waiting) - (self in type(self).waiting)
                self.limit_concurrency = self._limit + others
            super().handle_events()
            if self.headers is not None and self._head_timer is not None:
                self._stop_waiting()

        def connection_lost(self, exc: Exception | None) -> None:
            self._stop_waiting()
            super().connection_lost(exc)

        def _stop_waiting(self) -> None:
            if self._head_timer is not None:
                self._head_timer.cancel()
                self._head_timer = None
            type(self).waiting.pop(self, None)

        def _head_too_slow(self) -> None:
            self._stop_waiting()
            if self.headers is None and not self.transport.is_closing():
                type(self).slow_closed += 1
                self.transport.close()

    return HeaderTimeoutH11


def uvicorn_config(
    app: Any,
    *,
    host: str,
    port: int,
    limits: Limits | None = None,
    trusted_proxies: tuple[str, ...] = (),
    **options: Any,
) -> uvicorn.Config:
    """A uvicorn config with melfa's connection limits. ``X-Forwarded-For``/``-Proto`` are
    believed only from ``trusted_proxies`` (none by default: not even localhost)."""
    lim = limits or Limits()
    return uvicorn.Config(
        app,
        host=host,
        port=port,
        http=header_timeout_protocol(lim.header_timeout_s),
        ws="websockets-sansio",
        h11_max_incomplete_event_size=lim.header_bytes,
        timeout_keep_alive=max(1, round(lim.keep_alive_s)),
        limit_concurrency=lim.max_connections,
        ws_max_size=lim.ws_message_bytes,
        proxy_headers=bool(trusted_proxies),
        forwarded_allow_ips=list(trusted_proxies) if trusted_proxies else None,
        server_header=False,
        **options,
    )


__all__ = ["header_timeout_protocol", "uvicorn_config"]
