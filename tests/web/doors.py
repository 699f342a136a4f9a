"""A real `melfa serve` on a real TCP virtual controller whose every byte is traced, with
rosbridge on its own port, and a client of each of its doors (httpx, roslibpy): the tests
that ask the one policy at every door (test_every_door, test_lab_network) share it."""

from __future__ import annotations

import contextlib
import subprocess
import sys
import threading
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import roslibpy

from melfa.link.wrappers import load_trace
from tests.serving import free_port, melfa_serve, stop_process
from tests.waiting import wait_until

ADMIN = "admin-password-1"
FAST = ("--no-pacing", "--latency", "0")
"""The virtual controller as fast as it goes (the policy is tested, not the line)."""
POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def program(door: str) -> str:
    """A program only this door loads (its comment marks its bytes in the trace)."""
    return f"' door {door}\nSERVO ON\nMOV P1\nEND\n"


@dataclass
class Lab:
    url: str
    bridge: str
    trace: Path
    cookies: dict[str, tuple[str, str]] = field(default_factory=dict)
    """user -> (session token, CSRF token)"""
    tokens: dict[str, str] = field(default_factory=dict)
    """user -> personal access token"""

    def sent(self) -> bytes:
        """Every byte the server sent to the controller so far."""
        events = load_trace(self.trace.read_text(encoding="utf-8").splitlines())
        return b"".join(e.data for e in events if e.direction == "->")

    def rest(self, user: str, method: str, path: str, body: Any = None) -> httpx.Response:
        session, csrf = self.cookies[user]
        return httpx.request(
            method,
            self.url + path,
            json=body,
            headers={"x-csrf-token": csrf},
            cookies={"melfa_session": session},
            timeout=60,
        )

    def sign_in(self, user: str, password: str) -> None:
        """``user`` signed in (a cookie) and holding a personal access token."""
        signed = httpx.post(
            self.url + "/api/session", json={"username": user, "password": password}, timeout=30
        )
        assert signed.status_code == 200, signed.text
        self.cookies[user] = (signed.cookies["melfa_session"], signed.json()["csrf_token"])
        made = self.rest(user, "POST", "/api/tokens", {"label": "doors"})
        self.tokens[user] = made.json()["token"]

    def add_students(self, users: Iterable[str]) -> None:
        """Accounts made by the admin, each signed in (password ``<user>-password-12``)."""
        for user in users:
            password = f"{user}-password-12"
            made = self.rest(
                "admin", "POST", "/api/users", {"username": user, "password": password}
            )
            assert made.status_code == 201, made.text
            self.sign_in(user, password)

    def idle(self) -> bool:
        """The program ran to its end (or never started) and the arm is still."""
        state = self.rest("admin", "GET", "/api/robot/state").json()
        return not (state["running"] or state["program_running"] or state["moving"])

    def ros(self, user: str, mode: str) -> Any:
        ros = roslibpy.Ros(host=f"{self.bridge}/?token={self.tokens[user]}&mode={mode}")
        ros.run(timeout=20)
        return ros


@contextlib.contextmanager
def lab_server(data: Path, *options: str, preload: str | None = None) -> Iterator[Lab]:
    """`melfa serve` with ``options`` on a traced TCP virtual controller, the admin signed in.
    ``preload``: a program (its points `POINTS`) the controller holds before the server
    starts, loaded by `melfa upload` (the server never loaded it)."""
    sim_port, bridge_port = free_port(), free_port()
    sim = subprocess.Popen(
        [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{sim_port}", *FAST],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    trace = data / "robot.trace"
    try:
        if preload is not None:
            _upload(data, f"tcp://127.0.0.1:{sim_port}", preload)
        with melfa_serve(
            data,
            "--robot",
            f"tcp://127.0.0.1:{sim_port}",
            "--trace",
            str(trace),
            "--rosbridge-port",
            str(bridge_port),
            *options,
            admin_password=ADMIN,
            timeout=60,
        ) as url:
            lab = Lab(url, f"ws://127.0.0.1:{bridge_port}", trace)
            lab.sign_in("admin", ADMIN)
            yield lab
    finally:
        stop_process(sim)


@contextlib.contextmanager
def ann_holding(lab: Lab) -> Iterator[Lab]:
    """A new student, ann, holds the lab robot with the servo on, her first command (the
    lease is taken by it); she keeps a rosbridge connection open all along, as a student
    with the IDE open (a lease ends with its holder's last connection)."""
    lab.add_students(("ann",))
    with holding(lab, "ann"):
        yield lab


@contextlib.contextmanager
def holding(lab: Lab, user: str) -> Iterator[Lab]:
    """``user`` (signed in) holds the lab robot with the servo on, a rosbridge connection
    of theirs open all along."""
    holder = lab.ros(user, "melfa")
    try:
        assert lab.rest(user, "POST", "/api/robot/servo", {"on": True}).is_success
        yield lab
    finally:
        holder.close()


def _upload(data: Path, robot: str, program: str) -> None:
    """``program`` and `POINTS` into the controller at ``robot`` with `melfa upload`, once
    the virtual controller listens."""
    (data / "preload.MB4").write_text(program, encoding="utf-8")
    (data / "preload.POS").write_text(POINTS, encoding="utf-8")
    command = [sys.executable, "-m", "melfa", "upload", str(data / "preload.MB4")]
    command += ["--points", str(data / "preload.POS"), "--robot", robot]

    def uploaded() -> bool:
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
        return done.returncode == 0

    wait_until(uploaded, 60, what="melfa upload to the virtual controller")


class Errors:
    """``/execute_error`` as roslibpy delivers it (its own thread)."""

    def __init__(self) -> None:
        self.texts: list[str] = []
        self._lock = threading.Lock()

    def __call__(self, message: dict[str, Any]) -> None:
        with self._lock:
            self.texts.append(message["data"])

    def since(self, start: int) -> list[str]:
        with self._lock:
            return self.texts[start:]


def call(ros: Any, name: str, args: dict[str, Any] | None = None) -> dict[str, Any]:
    """A melfa rosbridge service, as roslibpy calls it."""
    kind = "std_srvs/SetBool" if name == "servo" else "std_srvs/Trigger"
    service = roslibpy.Service(ros, f"/melfa/{name}", kind)
    reply: dict[str, Any] = service.call(roslibpy.ServiceRequest(args or {}), timeout=60)
    return reply
