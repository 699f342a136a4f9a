"""One socket's server side in memory, for a race of one event-loop turn that no client
of a real socket can place (a cancel in the very turn a message arrives): Starlette's own
`WebSocket` on the ASGI channel uvicorn would hand the app."""

from __future__ import annotations

import asyncio
import json
from typing import Any

from starlette.websockets import WebSocket


class AsgiChannel:
    """The server's side of one socket, in memory: what uvicorn hands the app."""

    def __init__(self) -> None:
        self.incoming: asyncio.Queue[dict[str, Any]] = asyncio.Queue()
        self.sent: list[dict[str, Any]] = []

    async def receive(self) -> dict[str, Any]:
        return await self.incoming.get()

    async def send(self, message: dict[str, Any]) -> None:
        self.sent.append(message)

    def arrives(self, **message: Any) -> None:
        self.incoming.put_nowait({"type": "websocket.receive", "text": json.dumps(message)})

    async def accepted(self) -> WebSocket:
        scope = {"type": "websocket", "path": "/", "headers": [], "query_string": b""}
        websocket = WebSocket(scope, self.receive, self.send)
        self.incoming.put_nowait({"type": "websocket.connect"})
        await websocket.accept()
        return websocket


async def turns(n: int = 8) -> None:
    """Let the event loop go round ``n`` times (every task runs what it can)."""
    for _ in range(n):
        await asyncio.sleep(0)
