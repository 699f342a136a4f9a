"""Issue 15 through the real server: uvicorn on a loopback port, real WebSockets and
/rosbridge. Revoked sessions lose their sockets, STOP is not delayed by floods, throttling
never locks out the owner, limits refuse without growing memory, pages carry headers.
No test times anything: floods are held open by a latch and STOP must finish inside them."""

from __future__ import annotations

import json
import socket
import threading
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from melfa.store import Store
from melfa.web import WebSettings
from melfa.web.limits import Limits
from melfa.web.pools import PoolSizes
from tests.web.conftest import PASSWORDS, fast_service, make_store
from tests.web.live_server import LatchHasher, Live, live_server

ORIGIN_OK = None  # a non-browser client sends no Origin


def rss_kib() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    raise AssertionError("no VmRSS")


@pytest.fixture
def live(tmp_path: Path) -> Iterator[Live]:
    store = make_store(tmp_path / "data")
    limits = Limits(header_timeout_s=0.5, socket_recheck_s=0.2)
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), limits=limits)
    with live_server(store, settings) as server:
        yield server
    store.close()


def auth(token: str, csrf: str) -> dict[str, str]:
    return {"Cookie": f"melfa_session={token}", "X-CSRF-Token": csrf}


def ws_url(live: Live, path: str = "/api/ws") -> str:
    return f"ws://127.0.0.1:{live.port}{path}"


def open_ws(live: Live, token: str, path: str = "/api/ws") -> Any:
    return connect(
        ws_url(live, path), additional_headers={"Cookie": f"melfa_session={token}"}, legacy=True
    )


def until_type(ws: Any, kind: str, limit: int = 400, **match: Any) -> dict[str, Any]:
    for _ in range(limit):
        message = json.loads(ws.recv(timeout=30))
        if message.get("type") == kind and all(message.get(k) == v for k, v in match.items()):
            return message
    raise AssertionError(f"no {kind} with {match}")


def drain_until_closed(ws: Any) -> int | None:
    """Read until the server closes the socket; its close code."""
    try:
        for _ in range(10_000):
            ws.recv(timeout=30)
    except ConnectionClosed as closed:
        return closed.rcvd.code if closed.rcvd is not None else None
    finally:
        ws.close()
    raise AssertionError("the socket stayed open")


def _jogging_socket(live: Live, user: str = "ann") -> tuple[Any, str, str]:
    token, csrf = live.login(user)
    with live.client() as c:
        reply = c.post(
            "/api/robot/servo",
            json={"on": True},
            headers=auth(token, csrf),
        )
        assert reply.status_code == 200, reply.text
    ws = open_ws(live, token)
    until_type(ws, "hello")
    ws.send(json.dumps({"type": "jog_start", "frame": "joint", "axis": 0, "direction": 1, "id": 1}))
    until_type(ws, "ack", id=1)
    ws.send(json.dumps({"type": "jog_heartbeat"}))
    assert live.context.service.state.jogging
    return ws, token, csrf


def test_a_release_sent_right_behind_its_jog_start_stops_the_arm(live: Live) -> None:
    """A key tapped faster than the server answers: jog_start, a heartbeat, jog_release and a
    late heartbeat go out together. jog_start re-reads the session before moving (a hop to
    the store's pool) and jog_release does not, so a server handling a socket's messages
    side by side would let the release overtake the start, find no jog to end, and leave the
    arm jogging until the dead-man. One socket's messages are handled in order: the start is
    answered first, the release ends that jog, the late heartbeat does not revive it."""
    token, csrf = live.login("ann")
    with live.client() as c:
        reply = c.post("/api/robot/servo", json={"on": True}, headers=auth(token, csrf))
        assert reply.status_code == 200, reply.text
    ws = open_ws(live, token)
    try:
        until_type(ws, "hello")
        start = {"type": "jog_start", "frame": "joint", "axis": 0, "direction": 1, "id": 1}
        release = {"type": "jog_release", "id": 2}
        beat = {"type": "jog_heartbeat"}
        for message in (start, beat, release, beat):
            ws.send(json.dumps(message))
        acks: list[int] = []
        ended = None
        while len(acks) < 2 or ended is None:
            message = json.loads(ws.recv(timeout=30))
            assert message["type"] != "error", message
            if message["type"] == "ack":
                acks.append(message["id"])
            elif message["type"] == "jog" and not message["active"]:
                ended = message
        assert acks == [1, 2]
        assert ended["end"] == "released"
        ws.send(json.dumps({"type": "ping", "id": 3}))
        until_type(ws, "pong", id=3)  # after the late heartbeat was handled
        settled = _settled(ws)
        later = [until_type(ws, "state") for _ in range(3)]
        assert [state["joints"] for state in later] == [settled["joints"]] * 3, later
        assert not any(state["jogging"] for state in later)
    finally:
        ws.close()
    assert live.context.service.state.jogging is False


def _settled(ws: Any, limit: int = 200) -> dict[str, Any]:
    """The first state that repeats the joints of the one before it, not jogging. (The first
    state that merely says "not jogging" may carry joints read before the jog's last
    movement arrived; an arm still moving never repeats its joints.)"""
    before = until_type(ws, "state", jogging=False)
    for _ in range(limit):
        state = until_type(ws, "state", jogging=False)
        if state["joints"] == before["joints"] and not state["moving"]:
            return state
        before = state
    raise AssertionError(f"the arm never came to rest; last joints {before['joints']}")


def _sign_out(live: Live, token: str, csrf: str) -> None:
    with live.client() as c:
        reply = c.delete("/api/session", headers=auth(token, csrf))
        assert reply.status_code == 200


def _admin_resets_password(live: Live, token: str, csrf: str) -> None:
    admin, admin_csrf = live.login("admin")
    with live.client() as c:
        reply = c.put(
            "/api/users/ann/password",
            json={},
            headers=auth(admin, admin_csrf),
        )
        assert reply.status_code == 200, reply.text


def _admin_removes_account(live: Live, token: str, csrf: str) -> None:
    admin, admin_csrf = live.login("admin")
    with live.client() as c:
        reply = c.delete("/api/users/ann", headers=auth(admin, admin_csrf))
        assert reply.status_code == 200, reply.text


def _role_changed_by_another_process(live: Live, token: str, csrf: str) -> None:
    live.store.accounts.update_user("ann", role="instructor")  # as `melfa users` would


@pytest.mark.parametrize(
    "revoke",
    [_sign_out, _admin_resets_password, _admin_removes_account, _role_changed_by_another_process],
    ids=["sign-out", "password-reset", "account-removed", "role-changed-elsewhere"],
)
def test_a_revoked_sessions_open_socket_cannot_move_the_arm(live: Live, revoke: Any) -> None:
    ws, token, csrf = _jogging_socket(live)
    revoke(live, token, csrf)
    code = drain_until_closed(ws)  # closed by the server, not by us
    assert code == 1008
    assert not live.context.service.state.jogging  # its jog ended with it
    with pytest.raises(ConnectionClosed):
        ws.send(json.dumps({"type": "jog_start", "frame": "joint", "axis": 0, "direction": 1}))
        ws.recv(timeout=30)
    assert live.context.guard.count("ann") == 0


def test_a_signed_out_rosbridge_socket_is_closed_and_cannot_act(live: Live) -> None:
    token, csrf = live.login("ann")
    ws = open_ws(live, token, "/rosbridge")
    ws.send(json.dumps({"op": "call_service", "service": "/rosapi/topics", "id": "t1"}))
    assert json.loads(ws.recv(timeout=30))["op"] in ("service_response", "status")
    assert live.context.guard.count("ann") == 1
    _sign_out(live, token, csrf)
    drain_until_closed(ws)
    assert live.context.guard.count("ann") == 0


def test_rosbridge_refuses_a_cookie_from_origin_null(live: Live) -> None:
    token, _ = live.login("ann")
    ws = connect(
        ws_url(live, "/rosbridge"),
        additional_headers={"Cookie": f"melfa_session={token}", "Origin": "null"},
        legacy=True,
    )
    status = json.loads(ws.recv(timeout=30))
    assert status["op"] == "status" and "authentication failed" in status["msg"]
    drain_until_closed(ws)


def test_stop_answers_during_a_login_flood_held_open(tmp_path: Path) -> None:
    latch = threading.Event()
    hasher = LatchHasher(latch)
    store = make_store(tmp_path / "data")
    store.passwords.hasher = hasher
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
    flood = 60
    with live_server(store, settings) as live:
        latch.set()  # the operator signs in first
        token, csrf = live.login("ivy")
        latch.clear()
        signed_in = hasher.started

        def guess(i: int) -> int:
            with live.client(local_address=f"127.0.{i // 200 + 2}.{i % 200 + 1}") as c:
                reply = c.post("/api/session", json={"username": f"user{i}", "password": "nope"})
                return reply.status_code

        with ThreadPoolExecutor(flood) as pool:
            guesses = [pool.submit(guess, i) for i in range(flood)]
            pools = live.context.pools
            while pools.hash.pending + pools.hash.refused < flood:  # every guess is in
                threading.Event().wait(0.01)
            assert hasher.started - signed_in == settings.pools.hash_workers  # held
            with live.client() as c:
                stop = c.post(
                    "/api/robot/stop",
                    headers=auth(token, csrf),
                )
            assert stop.status_code == 200, stop.text
            finished = [g.result() for g in guesses if g.done()]
            latch.set()
            codes = [g.result() for g in guesses]
        # STOP came back while no admitted guess could have finished its hash (they wait
        # on the latch): only guesses refused at once (503, the pool full) were answered.
        assert set(finished) <= {503}
        assert codes.count(401) <= pools.hash.limit  # the flood was bounded
        assert codes.count(401) + codes.count(503) == flood
    store.close()


@pytest.mark.timeout(900)  # four 1 MB checks at niceness +10 crawl on a loaded machine
def test_stop_answers_during_the_largest_checks(tmp_path: Path) -> None:
    store = make_store(tmp_path / "data")
    sizes = PoolSizes(cpu_workers=2, cpu_queue=2, cpu_processes=True)  # as `melfa serve`
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service(), pools=sizes)
    program = "\n".join(f"{10 * i} MOV P{i % 50 + 1}" for i in range(1, 70_000))[:999_000]
    with live_server(store, settings) as live:
        token, csrf = live.login("ivy")
        ann, ann_csrf = live.login("ann")

        def check() -> int:
            with live.client() as c:
                reply = c.post(
                    "/api/check",
                    json={"program": program, "points": ""},
                    headers=auth(ann, ann_csrf),
                    timeout=600,  # queued behind the others on a busy machine
                )
                return reply.status_code

        cpu = live.context.pools.cpu
        with ThreadPoolExecutor(6) as pool:
            checks = [pool.submit(check) for _ in range(6)]
            while cpu.pending < sizes.cpu_workers:  # the big checks are running
                assert not [c.exception() for c in checks if c.done() and c.exception()]
                threading.Event().wait(0.01)
            with live.client() as c:
                stop = c.post(
                    "/api/robot/stop",
                    headers=auth(token, csrf),
                )
            still_checking = cpu.pending
            codes = [c.result() for c in checks]
        assert stop.status_code == 200
        # STOP did not wait for the pool: checks were still queued or running when it was
        # answered (on a loaded machine one of the first two may have finished by then).
        assert still_checking > 0
        assert codes.count(200) <= sizes.cpu_workers + sizes.cpu_queue
    store.close()


def test_a_locked_out_attacker_does_not_lock_out_the_owner(live: Live) -> None:
    with live.client("127.0.0.1") as owner:
        assert (
            owner.post(
                "/api/session", json={"username": "bob", "password": PASSWORDS["bob"]}
            ).status_code
            == 200
        )
    codes = []
    with live.client("127.0.0.66") as attacker:
        for _ in range(12):
            reply = attacker.post("/api/session", json={"username": "bob", "password": "guess-it"})
            codes.append(reply.status_code)
        assert codes[:5] == [401] * 5 and 429 in codes
        reply = attacker.post(
            "/api/session", json={"username": "bob", "password": PASSWORDS["bob"]}
        )
        assert reply.status_code == 429  # even the right password waits, from there
        message = reply.json()["error"]["message"]
        assert "wait" in message and int(reply.headers["retry-after"]) >= 1
    with live.client("127.0.0.1") as owner:  # her usual computer
        reply = owner.post("/api/session", json={"username": "bob", "password": PASSWORDS["bob"]})
        assert reply.status_code == 200


def test_a_hundred_concurrent_guesses_evaluate_at_most_the_allowed_number(live: Live) -> None:
    now = live.store.db.clock()
    live.store.db.clock = lambda: now  # the store's clock stands still: no back-off expires

    def guess(i: int) -> int:
        with live.client("127.0.0.77") as c:
            return c.post(
                "/api/session", json={"username": "cat", "password": f"guess-{i}"}
            ).status_code

    with ThreadPoolExecutor(100) as pool:
        codes = list(pool.map(guess, range(100)))
    allowed = live.store.logins.policy.max_failures_per_user
    assert codes.count(401) <= allowed  # evaluated (password checked)
    assert codes.count(401) + codes.count(429) + codes.count(503) == 100


def _raw(live: Live, data: bytes, *, read: bool = True) -> bytes:
    with socket.create_connection(("127.0.0.1", live.port), timeout=30) as s:
        s.sendall(data)
        if not read:
            return b""
        chunks = []
        while chunk := s.recv(65536):
            chunks.append(chunk)
        return b"".join(chunks)


def test_oversized_bodies_are_refused_before_they_are_read(live: Live) -> None:
    before = rss_kib()
    for _ in range(20):  # 20 × "200 MB" announced, a few bytes sent
        head = (
            b"POST /api/session HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
            b"Content-Length: 200000000\r\n\r\n{"
        )
        reply = _raw(live, head)
        assert reply.startswith(b"HTTP/1.1 413"), reply[:80]
    with live.client() as c:  # chunked, no length: counted and cut at the route's limit
        big = (b"x" * 65536 for _ in range(64))  # 4 MiB to an 8 KiB route
        reply = c.post("/api/session", content=big, headers={"Content-Type": "application/json"})
        assert reply.status_code == 413
    assert rss_kib() - before < 32 * 1024  # nowhere near 20 × 200 MB


def test_deep_json_is_refused_everywhere_without_a_server_error(live: Live) -> None:
    deep = "[" * 10_000 + "]" * 10_000
    token, csrf = live.login("ann")
    with live.client() as c:
        reply = c.post(
            "/api/check",
            content=deep,
            headers={**auth(token, csrf), "Content-Type": "application/json"},
        )
        assert 400 <= reply.status_code < 500, reply.text
    ws = open_ws(live, token)
    until_type(ws, "hello")
    ws.send('{"type": "ping", "x": ' + deep[:3000] + "}")
    error = until_type(ws, "error")
    assert "nests deeper" in error["error"]["message"]
    ws.close()
    bridge = open_ws(live, token, "/rosbridge")
    bridge.send('{"op": "publish", "msg": ' + deep + "}")
    status = json.loads(bridge.recv(timeout=30))
    assert status["op"] == "status" and "nests deeper" in status["msg"]
    bridge.close()


def test_slow_headers_are_cut_off(live: Live) -> None:
    before = rss_kib()
    socks = []
    for _ in range(50):
        s = socket.create_connection(("127.0.0.1", live.port), timeout=30)
        s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        socks.append(s)
    for s in socks:  # each is closed by the server (header timeout), never answered
        assert s.recv(1024) == b""
        s.close()
    with live.client() as c:
        assert c.get("/api/health").status_code == 200
    assert rss_kib() - before < 16 * 1024


def test_socket_messages_are_rate_limited(live: Live) -> None:
    token, _ = live.login("ann")
    ws = open_ws(live, token)
    until_type(ws, "hello")
    burst = live.context.settings.limits.ws_burst
    for i in range(burst * 3):
        try:
            ws.send(json.dumps({"type": "ping", "id": i}))
        except ConnectionClosed:
            break
    assert drain_until_closed(ws) == 1008


def test_pages_carry_security_headers_and_hosts_origins_are_checked(live: Live) -> None:
    with live.client() as c:
        for path in ("/login", "/api/health", "/static/js/main.js"):
            headers = c.get(path).headers
            assert "frame-ancestors 'none'" in headers["content-security-policy"]
            assert headers["x-content-type-options"] == "nosniff"
        reply = c.post(
            "/login",
            data={"username": "ann", "password": PASSWORDS["ann"]},
            headers={"Origin": "null"},
        )
        assert reply.status_code == 403  # a sandboxed or file: page cannot sign anyone in


def test_proxy_headers_are_not_believed_unless_configured(live: Live) -> None:
    with live.client() as c:
        for _ in range(6):
            c.post(
                "/api/session",
                json={"username": "ann", "password": "not-hers-1"},
                headers={"X-Forwarded-For": "10.9.9.9"},
            )
    rows = live.store.db.read(
        lambda conn: [r[0] for r in conn.execute("SELECT client_addr FROM login_attempts")]
    )
    assert rows and set(rows) == {"127.0.0.1"}


def test_host_allow_list(tmp_path: Path) -> None:
    store: Store = make_store(tmp_path / "data")
    settings = WebSettings(data_dir=tmp_path / "data", allowed_hosts=("127.0.0.1", "localhost"))
    with live_server(store, settings) as live, live.client() as c:
        assert c.get("/api/health").status_code == 200
        evil = c.get("/api/health", headers={"Host": "evil.example"})
        assert evil.status_code == 421
    store.close()


def test_own_password_change_keeps_this_session_and_refuses_weak_ones(live: Live) -> None:
    token, csrf = live.login("ann")
    other, _ = live.login("ann")
    ws = open_ws(live, other)
    until_type(ws, "hello")
    with live.client(headers={"Cookie": f"melfa_session={token}"}) as c:
        headers = {"X-CSRF-Token": csrf}
        weak = c.put(
            "/api/session/password",
            json={"current": PASSWORDS["ann"], "new": "password1"},
            headers=headers,
        )
        assert weak.status_code == 422 and "common" in weak.json()["error"]["message"]
        wrong = c.put(
            "/api/session/password",
            json={"current": "nope", "new": "ochre-lantern-42"},
            headers=headers,
        )
        assert wrong.status_code == 403
        good = c.put(
            "/api/session/password",
            json={"current": PASSWORDS["ann"], "new": "ochre-lantern-42"},
            headers=headers,
        )
        assert good.status_code == 200
        assert c.get("/api/session").status_code == 200  # this session stays
    assert drain_until_closed(ws) == 1008  # the other session's socket is gone
