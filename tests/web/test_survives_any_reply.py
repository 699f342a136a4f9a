"""The robot service survives any reply: through a real `melfa serve` (uvicorn) on a loopback
port, against the virtual controller with its origin lost (`****` on every position read),
and through a TCP relay that puts one `****` reply and one odd OPEN banner (a `²` in it)
into a healthy controller's traffic and hangs up once. The service keeps serving: STOP
works, the state says what is unknown, the link recovers by itself."""

from __future__ import annotations

import contextlib
import socket
import threading
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from melfa.sim import NO_PACING, SimConfig, TcpServer, VirtualController
from tests.serving import melfa_serve
from tests.waiting import wait_until

PASSWORD = "survive-any-reply-7731"
UNKNOWN_JOINTS = (
    b"QoKJ1;****;J2;****;J3;****;J4;****;J5;****;J6;****;;****,****;100;0.00;00000000\r"
)
ODD_BANNER = (
    b"QoK3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-6S;CRn-5xx;MELFA;05-07-14;Ver.K4a;ENG;"
    b"COPYRIGHT;1;1;\xc2\xb2;\r"
)


class Relay:
    """A TCP relay in front of a controller: replaces the reply to the next request that
    contains a given text (once), and can hang up once after a reply."""

    def __init__(self, upstream: tuple[str, int]) -> None:
        self.upstream = upstream
        self.replace: list[tuple[bytes, bytes]] = []
        self.hang_up_after: bytes | None = None
        self.opens = 0
        self._listener = socket.create_server(("127.0.0.1", 0))
        self._stop = threading.Event()
        threading.Thread(target=self._accept, daemon=True).start()

    @property
    def url(self) -> str:
        return f"tcp://127.0.0.1:{self._listener.getsockname()[1]}"

    def _accept(self) -> None:
        while not self._stop.is_set():
            try:
                client, _ = self._listener.accept()
            except OSError:
                return
            threading.Thread(target=self._serve, args=(client,), daemon=True).start()

    def _serve(self, client: socket.socket) -> None:
        with client, socket.create_connection(self.upstream) as server:
            buffer = b""
            while not self._stop.is_set():
                data = client.recv(4096)
                if not data:
                    return
                buffer += data
                while b"\r" in buffer:
                    line, buffer = buffer.split(b"\r", 1)
                    server.sendall(line + b"\r")
                    reply = b""
                    while not reply.endswith(b"\r"):
                        chunk = server.recv(4096)
                        if not chunk:
                            return
                        reply += chunk
                    if b"OPEN=" in line:
                        self.opens += 1
                    for index, (match, payload) in enumerate(self.replace):
                        if match in line:
                            reply = payload
                            del self.replace[index]
                            break
                    if reply:
                        client.sendall(reply)
                    if self.hang_up_after is not None and self.hang_up_after in line:
                        self.hang_up_after = None
                        return

    def close(self) -> None:
        self._stop.set()
        self._listener.close()


@contextlib.contextmanager
def served(tmp_path: Path, robot: str) -> Iterator[httpx.Client]:
    with (
        melfa_serve(tmp_path, "--robot", robot, admin_password=PASSWORD, timeout=60) as url,
        httpx.Client(base_url=url, timeout=10) as client,
    ):
        reply = client.post("/api/session", json={"username": "admin", "password": PASSWORD})
        assert reply.status_code == 200, reply.text
        client.headers["X-CSRF-Token"] = reply.json()["csrf_token"]
        yield client


def health(client: httpx.Client) -> str:
    return str(client.get("/api/health").json()["robot"]["link"])


def state(client: httpx.Client) -> dict[str, object]:
    reply = client.get("/api/robot/state")
    assert reply.status_code == 200, reply.text
    return dict(reply.json())


@pytest.fixture
def sim() -> Iterator[tuple[VirtualController, TcpServer]]:
    controller = VirtualController(SimConfig(strict=True))
    with TcpServer(controller, pacing=NO_PACING) as server:
        yield controller, server


def test_serve_against_a_controller_whose_origin_is_lost_keeps_serving(tmp_path: Path) -> None:
    controller = VirtualController(SimConfig(origin_set=False, strict=True))
    with TcpServer(controller, pacing=NO_PACING) as server, served(tmp_path, server.url) as web:
        # Several polls of `****` positions go by; the worker is still there.
        wait_until(lambda: state(web)["program"] is not None, 10, what="a state")
        for _ in range(3):
            reply = web.post("/api/robot/stop")
            assert reply.status_code == 200, reply.text
        now = state(web)
        assert now["link"] == "connected" and now["joints"] is None and now["pose"] is None
        assert health(web) == "connected"


def test_serve_through_a_relay_with_one_unknown_position_and_one_odd_banner(
    tmp_path: Path, sim: tuple[VirtualController, TcpServer]
) -> None:
    _, server = sim
    relay = Relay(server.address)
    try:
        with served(tmp_path, relay.url) as web:
            wait_until(lambda: state(web)["joints"] is not None, 10, what="joints read")
            opens = relay.opens
            # One `****` reply, then the line drops; the reconnect meets an odd banner.
            relay.replace += [(b"JPOSF", UNKNOWN_JOINTS), (b"OPEN=", ODD_BANNER)]
            relay.hang_up_after = b"JPOSF"
            wait_until(lambda: relay.opens > opens, 30, what="a reconnect")
            wait_until(lambda: health(web) == "connected", 30, what="the link back")
            wait_until(lambda: state(web)["joints"] is not None, 30, what="positions again")
            reply = web.post("/api/robot/stop")
            assert reply.status_code == 200, reply.text
            # A STOP whose answer never comes is "sent, not confirmed", never "ok".
            relay.replace.append((b";STOP", b""))
            reply = web.post("/api/robot/stop")
            assert reply.status_code == 504 and "not confirm" in reply.text, reply.text
            wait_until(lambda: web.post("/api/robot/stop").status_code == 200, 30, what="STOP")
    finally:
        relay.close()
