"""Issue 27's web holes through the real server (uvicorn on a loopback port): the password
oracle, binary frames and slow readers on /api/ws, /rosbridge before sign-in, rosapi
parameters, refused calls in the log, fragment amplification. No test times anything."""

from __future__ import annotations

import base64
import json
import logging
import os
import socket
import struct
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import ConnectionClosed, InvalidStatus
from websockets.sync.client import connect

from melfa.ros.rosbridge import MAX_FRAGMENTS, MIN_FRAGMENT_CHARS
from melfa.web import WebSettings
from melfa.web.limits import Limits
from melfa.web.pools import PoolSizes
from tests.waiting import wait_until
from tests.web.conftest import PASSWORDS, fast_service, make_store
from tests.web.live_server import Live, live_server
from tests.web.test_hardening import auth, open_ws, until_type, ws_url


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


@pytest.fixture
def slow_link(tmp_path: Path) -> Iterator[Live]:
    """A live server whose connections hold only 4 kB of unsent replies in the kernel (a
    browser on a slow link): writes to a client that does not read soon wait."""
    store = make_store(tmp_path / "data")
    limits = Limits(header_timeout_s=0.5, socket_recheck_s=0.2)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), limits=limits)
    with live_server(store, settings, send_buffer=4096) as server:
        yield server
    store.close()


def test_a_stop_behind_replies_a_slow_reader_cannot_take_is_read(slow_link: Live) -> None:
    """The slow-reader hole itself: 110 pings whose 4 kB pongs the client never reads.
    After a few dozen the server's writes to it wait; before the outbox (80ccbe4) the
    handler of the next message waited in its write, the queue of 32 filled, the reader
    waited to write the "too many messages" answer, and the STOP behind them was never
    read. Now every write goes through the socket's own outbox: the STOP is read and done
    (the audit has it) while the client still reads nothing."""
    token, _ = slow_link.login("ann")
    ws = RawClient(slow_link, token)
    try:
        padding = "x" * 4000
        for n in range(110):
            ws.send(json.dumps({"type": "ping", "id": f"{n}-{padding}"}).encode())
        ws.send(json.dumps({"type": "stop", "id": "the-stop"}).encode())

        def stopped() -> bool:
            return bool(slow_link.store.audit.query(action="robot.stop", actor="ann").entries)

        wait_until(stopped, 30, what="the STOP of a socket that does not read")
        # Reading at last, the client gets its answers, the STOP's among them.
        ws.sock.settimeout(30)
        received = b""
        while b'"the-stop"' not in received:
            chunk = ws.sock.recv(65536)
            assert chunk, "the server closed the socket"
            received += chunk
    finally:
        ws.close()


# ---------------------------------------------------------------- /rosbridge


def bridge(live: Live, token: str | None = None) -> Any:
    query = f"?token={token}" if token else ""
    return connect(ws_url(live, "/rosbridge") + query, legacy=True, max_size=None)


def replies(ws: Any, op: str, limit: int = 2000) -> dict[str, Any]:
    for _ in range(limit):
        message: dict[str, Any] = json.loads(ws.recv(timeout=30))
        if message.get("op") == op:
            return message
    raise AssertionError(f"no {op}")


def closed_with(ws: Any) -> int | None:
    try:
        for _ in range(1000):
            ws.recv(timeout=30)
    except ConnectionClosed as closed:
        return closed.rcvd.code if closed.rcvd is not None else None
    raise AssertionError("the socket stayed open")


def test_deep_json_before_sign_in_is_refused_with_a_close_code(
    live: Live, caplog: pytest.LogCaptureFixture
) -> None:
    ws = bridge(live)
    ws.send("[" * 100_000 + "]" * 100_000)
    assert closed_with(ws) == 1008
    assert not [r for r in caplog.records if r.levelno >= logging.ERROR], caplog.text


def test_sockets_signing_in_are_capped_and_counted(live: Live) -> None:
    """Sockets that never sign in take at most `max_sockets_signing_in` places; a signed-in
    client still gets in, and the places are given back when they go."""
    cap = live.context.settings.limits.max_sockets_signing_in
    waiting = [bridge(live) for _ in range(cap)]
    try:
        with pytest.raises(InvalidStatus):
            bridge(live)
        assert live.context.guard.signing_in == cap
        token, _ = live.login("ann")
        signed_in = bridge(live, token)
        signed_in.send(json.dumps({"op": "call_service", "service": "/rosapi/nodes", "id": 1}))
        assert replies(signed_in, "service_response")["result"] is True
        signed_in.close()
    finally:
        for ws in waiting:
            ws.close()
    wait_until(lambda: live.context.guard.signing_in == 0, what="the places given back")


def test_refused_service_calls_are_not_logged_as_errors(
    live: Live, caplog: pytest.LogCaptureFixture
) -> None:
    """Another student holds the lease: ann's calls are refused (her situation, no fault
    of the server's), answered, and logged at INFO."""
    caplog.set_level(logging.INFO, logger="melfa.ros")
    bob, bob_csrf = live.login("bob")
    with live.client() as c:
        assert c.post("/api/lease", headers=auth(bob, bob_csrf)).status_code == 200
    token, _ = live.login("ann")
    ws = bridge(live, token)
    try:
        for n in range(5):
            ws.send(json.dumps({"op": "call_service", "service": "/melfa/run", "id": n}))
            reply = replies(ws, "service_response")
            assert reply["values"]["success"] is False, reply
    finally:
        ws.close()
    refusals = [r for r in caplog.records if "service run" in r.getMessage()]
    assert len(refusals) == 5, caplog.text
    assert all(r.levelno == logging.INFO for r in refusals), caplog.text


def test_fragment_size_1_is_not_an_amplifier(live: Live) -> None:
    token, _ = live.login("ann")
    ws = bridge(live, token)
    try:
        ws.send(json.dumps({"op": "subscribe", "topic": "/joint_states", "fragment_size": 1}))
        parts: list[dict[str, Any]] = []
        while not parts or len(parts) < parts[0]["total"]:
            message = replies(ws, "fragment")
            if message["num"] == 0:
                parts = []
            parts.append(message)
    finally:
        ws.close()
    assert len(parts) <= MAX_FRAGMENTS
    assert all(len(p["data"]) >= MIN_FRAGMENT_CHARS for p in parts[:-1])
    whole = json.loads("".join(p["data"] for p in parts))
    assert whole["topic"] == "/joint_states"


def set_param(ws: Any, name: str, chars: int) -> dict[str, Any]:
    value = json.dumps("v" * chars)
    ws.send(
        json.dumps(
            {
                "op": "call_service",
                "service": "/rosapi/set_param",
                "args": {"name": name, "value": value},
                "id": name,
            }
        )
    )
    return replies(ws, "service_response")


def test_rosapi_parameters_are_bounded_and_given_back_on_close(tmp_path: Path) -> None:
    store = make_store(tmp_path / "data")
    limits = Limits(rosapi_param_chars=100_000, rosapi_param_chars_total=200_000)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), limits=limits)
    with live_server(store, settings) as live:
        token, _ = live.login("ann")
        budget = live.context.rosapi_params
        first = bridge(live, token)
        assert set_param(first, "/a", 60_000)["result"] is True
        refused = set_param(first, "/b", 60_000)
        assert refused["result"] is False and "per connection" in refused["values"]
        assert set_param(first, "/a", 90_000)["result"] is True, "a value replaced"
        others = [bridge(live, token) for _ in range(2)]
        assert [set_param(ws, "/a", 70_000)["result"] for ws in others] == [True, False]
        assert budget.used == 90_002 + 70_002, "each value's JSON text counted"
        first.close()
        wait_until(lambda: budget.used == 70_002, what="the closed socket's parameters freed")
        assert set_param(others[1], "/a", 70_000)["result"] is True
        for ws in others:
            ws.close()
        wait_until(lambda: budget.used == 0, what="every parameter freed")
    store.close()


# ---------------------------------------------------------------- slowloris


def test_slow_heads_cannot_hold_every_connection(tmp_path: Path) -> None:
    """More slow-header connections than the server's connection limit, held open (as an
    attacker who reopens each one cut keeps them): they do not count towards the limit,
    and /api/health answers every probe."""
    store = make_store(tmp_path / "data")
    limits = Limits(max_connections=100)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), limits=limits)
    slow: list[socket.socket] = []
    with live_server(store, settings) as live:
        try:
            for _ in range(150):
                s = socket.socket()
                s.bind(("127.0.0.2", 0))
                s.connect(("127.0.0.1", live.port))
                s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
                slow.append(s)
            with live.client() as c:
                probes = [c.get("/api/health").status_code for _ in range(5)]
        finally:
            for s in slow:
                s.close()
    store.close()
    assert probes == [200] * 5


# ---------------------------------------------------------------- loads and live checks


def test_a_load_is_not_refused_while_the_checks_are_full(tmp_path: Path) -> None:
    """Everyone's live checks fill the check pool (one worker, no waiting room): a
    student's *Load project* is still planned and loaded, in a pool of its own."""
    store = make_store(tmp_path / "data")
    sizes = PoolSizes(cpu_workers=1, cpu_queue=0)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), pools=sizes)
    program = "\n".join(f"{10 * i} MOV P{i % 50 + 1}" for i in range(1, 70_000))[:999_000]
    with live_server(store, settings) as live:
        token, csrf = live.login("ann")
        bob, bob_csrf = live.login("bob")

        def check() -> int:
            with live.client() as c:
                reply = c.post(
                    "/api/check",
                    json={"program": program, "points": ""},
                    headers=auth(bob, bob_csrf),
                )
                return reply.status_code

        cpu = live.context.pools.cpu
        with ThreadPoolExecutor(1) as pool:
            typing = pool.submit(check)
            wait_until(lambda: cpu.pending >= 1, what="a live check running")
            with live.client() as c:
                full = c.post(
                    "/api/check",
                    json={"program": "END\n", "points": ""},
                    headers=auth(bob, bob_csrf),
                )
                load = c.post(
                    "/api/robot/project",
                    json={
                        "program": "10 MOV P1\n20 END\n",
                        "points": "P1=(300,0,400,180,0,180)(7,0)\n",
                    },
                    headers=auth(token, csrf),
                )
            still_checking = not typing.done()
            typing.result()
    store.close()
    assert full.status_code == 503, "the check pool was full"
    assert load.status_code == 200, load.text
    assert still_checking, "the load was answered while the check pool was full"
