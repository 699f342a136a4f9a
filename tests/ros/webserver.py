"""The real web app (`melfa.web.create_app`, which includes the rosbridge router), served
by a real uvicorn on a free loopback port, and optionally the rosbridge port of its own
(`melfa.web.rosbridge_app.create_rosbridge_app`, what `melfa serve --rosbridge-port` runs)
on another."""

from __future__ import annotations

import contextlib
import socket
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import uvicorn
from argon2 import PasswordHasher
from fastapi import FastAPI

from melfa.service import ServiceConfig
from melfa.store import Store
from melfa.web import SESSION_COOKIE, WebSettings, create_app
from melfa.web.rosbridge_app import create_rosbridge_app
from tests.waiting import start_uvicorn

PASSWORDS = {"ann": "ann-password-12", "ivy": "ivy-password-12"}


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


@dataclass
class Server:
    app: FastAPI
    port: int
    store: Store
    bridge_port: int | None = None

    @property
    def bridge_url(self) -> str:
        """``ws://127.0.0.1:<rosbridge port>`` (as the thesis's page builds it)."""
        assert self.bridge_port is not None
        return f"ws://127.0.0.1:{self.bridge_port}"

    def token(self, username: str, label: str = "test") -> str:
        """A new personal access token (what `melfa users token` prints)."""
        user = self.store.accounts.get_user(username)
        return self.store.tokens.create(user, label).token

    @property
    def http(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def ws_url(self) -> str:
        return f"ws://127.0.0.1:{self.port}/rosbridge"

    def login(self, username: str) -> str:
        """Sign in over HTTP; the session token (the cookie's value)."""
        response = httpx.post(
            f"{self.http}/api/session",
            json={"username": username, "password": PASSWORDS[username]},
            timeout=30,
        )
        assert response.status_code == 200, response.text
        token: str = response.cookies[SESSION_COOKIE]
        return token


def _start(app: FastAPI, port: int) -> tuple[uvicorn.Server, threading.Thread]:
    config = uvicorn.Config(
        app, host="127.0.0.1", port=port, log_level="warning", ws="websockets-sansio"
    )
    return start_uvicorn(config)


@contextlib.contextmanager
def serve(
    data_dir: Path,
    *,
    rosbridge_mode: str | None = None,
    service_config: ServiceConfig | None = None,
) -> Iterator[Server]:
    """The web app; with ``rosbridge_mode`` also the rosbridge port in that mode."""
    store = Store.open_dir(
        data_dir, hasher=PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)
    )
    store.accounts.create_user("ann", PASSWORDS["ann"], group="G1")
    store.accounts.create_user("ivy", PASSWORDS["ivy"], role="instructor")
    config = service_config or ServiceConfig(idle_poll_s=0.2)
    settings = WebSettings(data_dir=data_dir, service_config=config)
    app = create_app(settings, store=store)
    port = free_port()
    running = [_start(app, port)]
    bridge_port = None
    if rosbridge_mode is not None:
        bridge_port = free_port()
        running.append(_start(create_rosbridge_app(app, rosbridge_mode), bridge_port))
    try:
        yield Server(app, port, store, bridge_port)
    finally:
        for server, thread in reversed(running):
            server.should_exit = True
            thread.join(30)
        store.close()
