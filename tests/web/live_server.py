"""A real uvicorn on a loopback port, in a thread of the test process (so tests can read the
server's counters), started the way `melfa serve` starts it (`melfa.web.server`)."""

from __future__ import annotations

import asyncio
import socket
import threading
from collections.abc import Coroutine, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import httpx
from argon2 import PasswordHasher

from melfa.store import Store
from melfa.web import WebSettings, create_app
from melfa.web.context import WebContext
from melfa.web.server import uvicorn_config
from tests.waiting import start_uvicorn
from tests.web.conftest import PASSWORDS, fast_service, make_store

T = TypeVar("T")

CHEAP = PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)


class LatchHasher(PasswordHasher):
    """Real Argon2 whose verifications wait for ``latch``: a login flood that cannot end
    until the test says so (no timing in the test)."""

    def __init__(self, latch: threading.Event) -> None:
        super().__init__(time_cost=1, memory_cost=64, parallelism=1)
        self.latch = latch
        self.started = 0
        self.lock = threading.Lock()

    def verify(self, hash: str | bytes, password: str | bytes) -> bool:
        with self.lock:
            self.started += 1
        self.latch.wait(60)
        return super().verify(hash, password)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@dataclass
class Live:
    url: str
    port: int
    app: Any
    store: Store
    loop: asyncio.AbstractEventLoop | None = None
    """The server's event loop (`on_loop`)."""

    def on_loop(self, work: Coroutine[Any, Any, T]) -> T:
        """Run ``work`` on the server's event loop and give its result (state that only
        the loop may touch)."""
        assert self.loop is not None
        return asyncio.run_coroutine_threadsafe(work, self.loop).result(60)

    @property
    def context(self) -> WebContext:
        context: WebContext = self.app.state.web
        return context

    def client(self, local_address: str = "127.0.0.1", **kw: Any) -> httpx.Client:
        transport = httpx.HTTPTransport(local_address=local_address)
        return httpx.Client(base_url=self.url, transport=transport, timeout=60, **kw)

    def login(self, username: str) -> tuple[str, str]:
        """(session token, CSRF token) of a fresh sign-in."""
        with self.client() as c:
            reply = c.post(
                "/api/session", json={"username": username, "password": PASSWORDS[username]}
            )
        assert reply.status_code == 200, reply.text
        return reply.cookies["melfa_session"], reply.json()["csrf_token"]


@contextmanager
def live_server(
    store: Store, settings: WebSettings, *, send_buffer: int | None = None, **options: Any
) -> Iterator[Live]:
    """``options``: more of `create_app`'s (``queue_clock``). ``send_buffer``: the bytes
    the kernel holds for each connection's unsent replies (SO_SNDBUF, inherited from the
    listening socket; fixed, so not grown by the kernel): a browser on a slow link fills
    it, and the server's next write to it waits."""
    port = free_port()
    app = create_app(settings, store=store, **options)
    config = uvicorn_config(
        app,
        host="127.0.0.1",
        port=port,
        limits=settings.limits,
        log_level="warning",
        lifespan="on",
    )
    server, thread = start_uvicorn(config)
    if send_buffer is not None:
        for listening in server.servers:
            for sock in listening.sockets:
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, send_buffer)
    try:
        loop = server.servers[0].get_loop()
        yield Live(f"http://127.0.0.1:{port}", port, app, store, loop)
    finally:
        server.should_exit = True
        thread.join(30)


@contextmanager
def fresh_live(tmp_path: Path) -> Iterator[Live]:
    """`live_server` on a new store under ``tmp_path`` with the test accounts
    (`make_store`), default settings and a fast-polling service."""
    store = make_store(tmp_path / "data")
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
    try:
        with live_server(store, settings) as server:
            yield server
    finally:
        store.close()
