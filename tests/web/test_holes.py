"""Issue 27's web holes through the real server (uvicorn on a loopback port): the password
oracle, binary frames and slow readers on /api/ws, /rosbridge before sign-in, rosapi
parameters, refused calls in the log, fragment amplification. No test times anything."""

from __future__ import annotations

import base64
import json
import os
import socket
import struct
from collections.abc import Iterator
from pathlib import Path

import pytest

from melfa.web import WebSettings
from melfa.web.limits import Limits
from tests.waiting import wait_until
from tests.web.conftest import PASSWORDS, fast_service, make_store
from tests.web.live_server import Live, live_server
from tests.web.test_hardening import auth, open_ws, until_type


@pytest.fixture
def live(tmp_path: Path) -> Iterator[Live]:
    store = make_store(tmp_path / "data")
    limits = Limits(header_timeout_s=0.5, socket_recheck_s=0.2)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), limits=limits)
    with live_server(store, settings) as server:
        yield server
    store.close()


# ---------------------------------------------------------------- the password oracle


def test_wrong_current_passwords_count_as_failed_sign_ins(live: Live) -> None:
    """A borrowed session guessing its owner's password through the password change is
    throttled like a sign-in: after the free failures the right password is refused too
    (429), so the answer tells the guesser nothing."""
    token, csrf = live.login("ann")
    statuses = []
    with live.client() as c:
        for n in range(20):
            reply = c.put(
                "/api/session/password",
                json={"current": f"guess-number-{n}", "new": "a-brand-new-secret-77"},
                headers=auth(token, csrf),
            )
            statuses.append(reply.status_code)
        right = c.put(
            "/api/session/password",
            json={"current": PASSWORDS["ann"], "new": "a-brand-new-secret-77"},
            headers=auth(token, csrf),
        )
        signing_in = c.post("/api/session", json={"username": "ann", "password": PASSWORDS["ann"]})
    assert set(statuses) == {403, 429}, statuses
    assert statuses.count(403) <= 8, statuses
    assert right.status_code == 429 and "Retry-After" in right.headers
    assert signing_in.status_code == 429, "the guesses count for the account's sign-ins too"


# ---------------------------------------------------------------- /api/ws transport


def test_a_binary_frame_is_answered_and_the_socket_stays(live: Live) -> None:
    token, _ = live.login("ann")
    ws = open_ws(live, token)
    try:
        until_type(ws, "hello")
        ws.send(b"\x00\x01binary")
        error = until_type(ws, "error")
        assert error["error"]["code"] == "bad-message" and "binary" in error["error"]["message"]
        ws.send(json.dumps({"type": "ping", "id": 5}))
        assert until_type(ws, "pong")["id"] == 5
    finally:
        ws.close()


class RawClient:
    """A WebSocket client on a bare socket with a tiny receive window that reads nothing
    after the handshake unless asked: the server's writes to it block at once."""

    def __init__(self, live: Live, token: str, path: str = "/api/ws") -> None:
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 2048)
        self.sock.connect(("127.0.0.1", live.port))
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(
            f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{live.port}\r\nUpgrade: websocket\r\n"
            f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
            f"Sec-WebSocket-Version: 13\r\nCookie: melfa_session={token}\r\n\r\n".encode()
        )
        head = b""
        while b"\r\n\r\n" not in head:
            head += self.sock.recv(1)
        assert head.startswith(b"HTTP/1.1 101"), head

    def send(self, payload: bytes, opcode: int = 1) -> None:
        mask = os.urandom(4)
        size = len(payload)
        if size < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | size)
        elif size < 65536:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, size)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, size)
        body = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(head + mask + body)

    def close(self) -> None:
        self.sock.close()


def test_a_client_that_does_not_read_still_has_its_stop_read(live: Live) -> None:
    """Big pings whose pongs the client never reads fill the server's send buffers and the
    queue of messages waiting; the STOP sent behind them is still read and done (the
    audit has it) before the client reads anything."""
    token, _ = live.login("ann")
    ws = RawClient(live, token)
    try:
        padding = "x" * 4000
        for n in range(110):
            ws.send(json.dumps({"type": "ping", "id": f"{n}-{padding}"}).encode())
        ws.send(json.dumps({"type": "stop", "id": "the-stop"}).encode())

        def stopped() -> bool:
            return bool(live.store.audit.query(action="robot.stop", actor="ann").entries)

        wait_until(stopped, 30, what="the STOP of a socket that does not read")
    finally:
        ws.close()
