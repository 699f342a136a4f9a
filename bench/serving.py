"""What the benchmarks that drive a real `melfa serve` process share: a free loopback
port, a server on a temporary database with a class of accounts, signing in as a person
would, the server's memory, percentiles and the machine's load (printed beside figures,
since the machine may be shared).

Not a benchmark itself: imported by the ``bench_*.py`` scripts beside it."""

from __future__ import annotations

import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx
from argon2 import PasswordHasher

ADMIN_PASSWORD = "bench-lantern-9"
STUDENT_PASSWORD = "student-lantern-9"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def rss_mib(pid: int) -> float:
    """A process's resident memory in MiB."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def p(values: list[float], q: float) -> float:
    """The ``q`` quantile (0..1) of ``values`` by rank; NaN for none."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] if ordered else float("nan")


def ms(values: list[float]) -> str:
    if not values:
        return "no samples"
    return f"p50 {statistics.median(values) * 1000:6.0f} ms  p95 {p(values, 0.95) * 1000:6.0f} ms"


def load() -> str:
    """The 1-, 5- and 15-minute load averages."""
    return " ".join(Path("/proc/loadavg").read_text().split()[:3])


@contextmanager
def serve(
    students: int = 0, *, instructors: int = 0, args: tuple[str, ...] = (), cheap: bool = True
) -> Iterator[tuple[str, int]]:
    """A `melfa serve` process (in-process virtual lab robot) on a fresh database with an
    admin, ``instructors`` instructors ``teach``, ``teach1`` … and ``students`` students
    ``s00`` … (cheap Argon2 for the accounts made here unless ``cheap`` is False); yields
    its URL and pid, and stops it."""
    data = Path(tempfile.mkdtemp(prefix="melfa-bench-"))
    if students or instructors:
        from melfa.store import Store

        hasher = PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)
        with Store.open_dir(data, hasher=hasher) if cheap else Store.open_dir(data) as store:
            store.accounts.ensure_admin(ADMIN_PASSWORD)
            for n in range(instructors):
                name = "teach" if n == 0 else f"teach{n}"
                store.accounts.create_user(name, STUDENT_PASSWORD, role="instructor")
            for n in range(students):
                store.accounts.create_user(f"s{n:02d}", STUDENT_PASSWORD)
    port = free_port()
    env = {**os.environ, "MELFA_ADMIN_PASSWORD": ADMIN_PASSWORD}
    env.pop("MELFA_ROBOT", None)
    command = [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)]
    server = subprocess.Popen(
        [*command, *args], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    url = f"http://127.0.0.1:{port}"
    try:
        wait_healthy(url)
        yield url, server.pid
    finally:
        server.terminate()
        server.wait(30)


def wait_healthy(url: str) -> None:
    """Until the server at ``url`` answers ``/api/health`` (a minute at most)."""
    for _ in range(600):
        try:
            if httpx.get(url + "/api/health", timeout=2).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        time.sleep(0.1)


def sign_in(url: str, user: str, password: str = STUDENT_PASSWORD) -> dict[str, str]:
    """Headers of a fresh session (cookie and CSRF token, and the bare ``token``); asked
    again, as a person would, while the server says "too many at once" (a class signing
    in together from one address: 16 at once per address)."""
    with httpx.Client(base_url=url, timeout=60) as c:
        for _ in range(100):
            reply = c.post("/api/session", json={"username": user, "password": password})
            if reply.status_code not in (429, 503):
                break
            time.sleep(1.0)
        reply.raise_for_status()
        token, csrf = reply.cookies["melfa_session"], reply.json()["csrf_token"]
    return {"Cookie": f"melfa_session={token}", "X-CSRF-Token": csrf, "token": token}
