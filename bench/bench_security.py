"""Security benchmark: STOP latency idle and under abuse, and the server's memory after a
bounded abuse run against idle — all in one run against a real `melfa serve` process
(real Argon2, the in-process virtual controller, a temporary database).

1. p50/p95 of ``POST /api/robot/stop`` with nothing else going on;
2. the same while a login flood (``--flood`` concurrent wrong sign-ins, repeated) and the
   largest allowed ``/api/check`` calls (1,000,000-character programs) run;
3. the server's resident memory idle, then after: 20 bodies announcing 200 MB, 300
   slow-header connections, 10,000-deep JSON, the flood and the checks.

    .venv/bin/python bench/bench_security.py [--flood 120] [--stops 40]
"""

from __future__ import annotations

import argparse
import socket
import statistics
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import httpx

from serving import ADMIN_PASSWORD as PASSWORD
from serving import p, rss_mib, serve


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--flood", type=int, default=120)
    parser.add_argument("--stops", type=int, default=40)
    args = parser.parse_args()
    with serve(cheap=False) as (url, pid):
        port = int(url.rsplit(":", 1)[1])
        with httpx.Client(base_url=url, timeout=60) as c:
            reply = c.post("/api/session", json={"username": "admin", "password": PASSWORD})
            token, csrf = reply.cookies["melfa_session"], reply.json()["csrf_token"]
        headers = {"Cookie": f"melfa_session={token}", "X-CSRF-Token": csrf}

        def stops(n: int) -> list[float]:
            out = []
            with httpx.Client(base_url=url, timeout=60, headers=headers) as c:
                for _ in range(n):
                    started = time.perf_counter()
                    assert c.post("/api/robot/stop").status_code == 200
                    out.append(time.perf_counter() - started)
                    time.sleep(0.02)
            return out

        idle = stops(args.stops)
        idle_rss = rss_mib(pid)

        program = "\n".join(f"{10 * i} MOV P{i % 50 + 1}" for i in range(1, 70_000))[:999_000]
        stop_flag = threading.Event()
        counts = {"logins": 0, "checks": 0}

        def flood(i: int) -> None:
            with httpx.Client(base_url=url, timeout=60) as c:
                while not stop_flag.is_set():
                    c.post("/api/session", json={"username": f"x{i}", "password": "wrong-1"})
                    counts["logins"] += 1

        def check() -> None:
            with httpx.Client(base_url=url, timeout=120, headers=headers) as c:
                while not stop_flag.is_set():
                    c.post("/api/check", json={"program": program, "points": ""})
                    counts["checks"] += 1

        def abuse() -> None:
            head = (
                b"POST /api/check HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 200000000\r\n\r\n{"
            )
            for _ in range(20):
                with socket.create_connection(("127.0.0.1", port), timeout=30) as s:
                    s.sendall(head)
                    s.recv(4096)
            slow = []
            for _ in range(300):
                s = socket.create_connection(("127.0.0.1", port), timeout=30)
                s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
                slow.append(s)
            for s in slow:
                s.recv(16)
                s.close()
            deep = "[" * 10_000 + "]" * 10_000
            with httpx.Client(base_url=url, timeout=60, headers=headers) as c:
                c.post("/api/check", content=deep, headers={"Content-Type": "application/json"})

        with ThreadPoolExecutor(args.flood + 8) as pool:
            jobs = [pool.submit(flood, i) for i in range(args.flood)]
            jobs += [pool.submit(check) for _ in range(6)]
            time.sleep(2.0)  # the flood and the checks are under way
            loaded = stops(args.stops)
            abuse()
            stop_flag.set()
            for job in jobs:
                job.result()
        time.sleep(1.0)
        after_rss = rss_mib(pid)

    print(
        f"STOP idle:        p50 {statistics.median(idle) * 1000:7.1f} ms   "
        f"p95 {p(idle, 0.95) * 1000:7.1f} ms"
    )
    print(
        f"STOP under load:  p50 {statistics.median(loaded) * 1000:7.1f} ms   "
        f"p95 {p(loaded, 0.95) * 1000:7.1f} ms  ({args.flood} concurrent wrong logins, "
        f"6 × 1,000,000-char checks; {counts['logins']} logins, {counts['checks']} checks answered)"
    )
    print(f"  = {p(loaded, 0.95) / p(idle, 0.95):.1f} × idle p95; budget 500 ms")
    print(
        f"server memory: idle {idle_rss:.0f} MiB, after abuse {after_rss:.0f} MiB "
        f"(= {after_rss / idle_rss:.2f} ×; abuse: 20 × 200 MB bodies announced, 300 slow "
        "headers, 10,000-deep JSON, the flood and the checks)"
    )


if __name__ == "__main__":
    main()
