"""Web benchmarks: many WebSocket viewers against the poll rate, and /api/check latency.

Runs `melfa serve`'s app under uvicorn in a thread (virtual controller in process, a
temporary database), then:

1. state rate with 1 viewer vs with 60 concurrent viewers: snapshots the service makes
   per second (its poll rate) and snapshots each viewer receives per second (capped by
   the per-socket throttle, `WebSettings.snapshot_hz`);
2. p50/p95 latency of `POST /api/check` for a 1,000-line program with its points.

    .venv/bin/python bench/bench_web.py [--viewers 60] [--seconds 3]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import socket
import statistics
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx
import uvicorn
from argon2 import PasswordHasher
from websockets.asyncio.client import connect

from melfa.store import Store
from melfa.web import CSRF_HEADER, SESSION_COOKIE, WebSettings, create_app

PASSWORD = "bench-password-1"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def program_lines(n: int) -> tuple[str, str]:
    body = [
        "SERVO ON",
        "OVRD 50",
        "*LOOP",
        "MOV P1",
        "MVS P2",
        "HOPEN 1",
        "DLY 0.2",
        "M1 = M1 + 1",
        "IF M1 > 10 THEN *DONE",
        "HCLOSE 1",
    ]
    lines = [body[i % len(body)] if i % len(body) != 2 else f"*L{i}" for i in range(n - 3)]
    lines += ["GOTO *L2", "*DONE", "END"]
    points = "DEF POS P1=(300,0,400,180,0,180)(7,0)\nDEF POS P2=(350,50,350,180,0,180)(7,0)\n"
    return "\n".join(lines) + "\n", points


class Server:
    def __init__(self, data: Path) -> None:
        self.store = Store.open_dir(data, hasher=PasswordHasher(1, 64, 1))
        self.store.accounts.create_user("viewer", PASSWORD, role="student")
        self.port = free_port()
        self.app = create_app(WebSettings(data_dir=data), store=self.store)
        config = uvicorn.Config(self.app, port=self.port, log_level="warning", access_log=False)
        self.server = uvicorn.Server(config)
        self.thread = threading.Thread(target=self.server.run, daemon=True)

    def __enter__(self) -> Server:
        self.thread.start()
        while not self.server.started:
            time.sleep(0.02)
        return self

    def __exit__(self, *exc: object) -> None:
        self.server.should_exit = True
        self.thread.join(10)
        self.store.close()

    @property
    def seq(self) -> int:
        return int(self.app.state.web.service.state.seq)


async def viewers(server: Server, token: str, n: int, seconds: float) -> dict[str, float]:
    url = f"ws://127.0.0.1:{server.port}/api/ws"
    headers = {"Cookie": f"{SESSION_COOKIE}={token}", "Origin": f"http://127.0.0.1:{server.port}"}
    counts = [0] * n

    async def view(i: int) -> None:
        async with connect(url, additional_headers=headers, max_queue=None) as ws:
            while True:
                message = json.loads(await ws.recv())
                if message["type"] == "state":
                    counts[i] += 1

    tasks = [asyncio.create_task(view(i)) for i in range(n)]
    await asyncio.sleep(1.0)  # connect and settle
    before, seq0, t0 = list(counts), server.seq, time.perf_counter()
    await asyncio.sleep(seconds)
    seq1, t1 = server.seq, time.perf_counter()
    got = [after - first for after, first in zip(counts, before, strict=True)]
    for task in tasks:
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)
    elapsed = t1 - t0
    return {
        "service": (seq1 - seq0) / elapsed,
        "mean": statistics.mean(got) / elapsed,
        "min": min(got) / elapsed,
    }


def check_latency(base: str, token: str, csrf: str, runs: int) -> tuple[float, float, int]:
    program, points = program_lines(1000)
    headers = {"Cookie": f"{SESSION_COOKIE}={token}", CSRF_HEADER: csrf}
    times = []
    with httpx.Client(base_url=base, headers=headers, timeout=30) as client:
        body: dict[str, Any] = {"program": program, "points": points}
        diagnostics = len(client.post("/api/check", json=body).json()["program"]["diagnostics"])
        for _ in range(runs):
            started = time.perf_counter()
            response = client.post("/api/check", json=body)
            times.append((time.perf_counter() - started) * 1000)
            assert response.status_code == 200, response.text
    times.sort()
    return statistics.median(times), times[int(0.95 * (len(times) - 1))], diagnostics


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--viewers", type=int, default=60)
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--check-runs", type=int, default=40)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp, Server(Path(tmp)) as server:
        base = f"http://127.0.0.1:{server.port}"
        login = httpx.post(f"{base}/api/session", json={"username": "viewer", "password": PASSWORD})
        token, csrf = login.cookies[SESSION_COOKIE], login.json()["csrf_token"]
        one = asyncio.run(viewers(server, token, 1, args.seconds))
        many = asyncio.run(viewers(server, token, args.viewers, args.seconds))
        p50, p95, found = check_latency(base, token, csrf, args.check_runs)
    hz = WebSettings().snapshot_hz
    print(f"state streaming (virtual controller in process, per-socket cap {hz:g}/s)")
    print(f"{'viewers':>8} {'service snapshots/s':>20} {'per viewer/s (mean)':>20} {'min':>8}")
    for n, r in ((1, one), (args.viewers, many)):
        print(f"{n:>8} {r['service']:>20.1f} {r['mean']:>20.1f} {r['min']:>8.1f}")
    ratio = many["service"] / one["service"] if one["service"] else float("nan")
    print(f"poll rate with {args.viewers} viewers / with 1: {ratio:.2f}")
    print()
    print(
        f"POST /api/check, 1,000-line program + points ({found} diagnostics), "
        f"{args.check_runs} runs"
    )
    print(f"{'p50 ms':>8} {'p95 ms':>8}")
    print(f"{p50:>8.1f} {p95:>8.1f}")


if __name__ == "__main__":
    main()
