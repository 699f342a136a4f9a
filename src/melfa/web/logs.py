"""Structured logs: one JSON object per line, for requests and robot operations.

`JsonFormatter` turns any record into JSON (the message plus the fields passed with
``extra={"fields": {...}}``); `RequestLog` is a small ASGI middleware that logs method,
path, status, duration and user of every HTTP request. `melfa serve` installs the
formatter on stderr; libraries and tests leave handlers alone.
"""

from __future__ import annotations

import datetime as dt
import json
import logging
import time
from typing import Any

from starlette.types import ASGIApp, Message, Receive, Scope, Send

request_log = logging.getLogger("melfa.web.request")
robot_log = logging.getLogger("melfa.web.robot")


class JsonFormatter(logging.Formatter):
    """``{"at": ..., "level": ..., "logger": ..., "message": ..., **fields}``."""

    def format(self, record: logging.LogRecord) -> str:
        out: dict[str, Any] = {
            "at": dt.datetime.fromtimestamp(record.created, dt.UTC).isoformat(),
            "level": record.levelname.lower(),
            "logger": record.name,
            "message": record.getMessage(),
        }
        fields = getattr(record, "fields", None)
        if isinstance(fields, dict):
            out.update(fields)
        if record.exc_info:
            out["exception"] = self.formatException(record.exc_info)
        return json.dumps(out, default=str, ensure_ascii=False)


def configure(level: int = logging.INFO) -> None:
    """JSON lines on stderr for the melfa loggers (used by `melfa serve`)."""
    handler = logging.StreamHandler()
    handler.setFormatter(JsonFormatter())
    root = logging.getLogger("melfa")
    root.handlers[:] = [handler]
    root.setLevel(level)
    root.propagate = False


class RequestLog:
    """ASGI middleware: one log line per HTTP request (WebSockets log their own)."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        scope.setdefault("state", {})
        started = time.perf_counter()
        status = 500

        async def watch(message: Message) -> None:
            nonlocal status
            if message["type"] == "http.response.start":
                status = message["status"]
            await send(message)

        try:
            await self.app(scope, receive, watch)
        finally:
            state = scope.get("state") or {}
            request_log.info(
                "%s %s %s",
                scope["method"],
                scope["path"],
                status,
                extra={
                    "fields": {
                        "method": scope["method"],
                        "path": scope["path"],
                        "status": status,
                        "ms": round((time.perf_counter() - started) * 1000, 2),
                        "user": state.get("user"),
                    }
                },
            )


__all__ = ["JsonFormatter", "RequestLog", "configure", "request_log", "robot_log"]
