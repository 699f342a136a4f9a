"""Issue 27's web holes, measured in one run against a real `melfa serve` process (the
in-process virtual controller, a temporary database):

1. memory after a rosapi parameter flood: 5 rounds of one /rosbridge socket storing
   100 × 0.9 MB parameters with ``set_param``, then closing (bounded, given back);
2. ``/api/health`` and STOP (REST) under a reconnecting slowloris (450 slow-header
   connections, each reopened as soon as it is cut: more than the connection limit);
3. STOP (REST) while one student's 8 /rosbridge sockets subscribe with ``fragment_size: 1``;
4. a class: ``--students`` students each typing (a check a second), autosaving (every 5 s)
   and running a looping program on their private simulator (the first *Load project*
   press counted when refused), and an instructor jogging the lab robot, for ``--minutes``:
   STOP p95 from REST and from the socket (budget 0.5 s) and their ratio in the same run
   (both under the same load: less moved by the machine's), load refusals (goal 0), and the
   server's memory per running private simulator (its growth after the first minute).

The load of the class runs in a child process, so the measuring process's own threads do
not slow its STOPs. The machine may be shared: the load average is printed with the figures.

    .venv/bin/python bench/bench_holes.py [--students 40] [--minutes 3]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import selectors
import socket
import statistics
import threading
import time
from collections.abc import Callable
from contextlib import suppress
from typing import Any

import httpx
from websockets.sync.client import connect

from serving import ADMIN_PASSWORD as PASSWORD
from serving import load, ms, p, rss_mib, serve, sign_in

LOOP = "10 MOV P1\n20 MOV P2\n30 GOTO 10\n"
LOOP_POINTS = "P1=(300,0,400,180,0,180)(7,0)\nP2=(300,100,450,180,0,180)(7,0)\n"
TYPING = "\n".join(f"{10 * i} MOV P{i % 9 + 1}" for i in range(1, 400)) + "\n"


def rest_stops(url: str, who: dict[str, str], n: int, gap: float = 0.1) -> list[float]:
    headers = {k: v for k, v in who.items() if k != "token"}
    out = []
    with httpx.Client(base_url=url, timeout=60, headers=headers) as c:
        for _ in range(n):
            started = time.perf_counter()
            reply = c.post("/api/robot/stop")
            if reply.status_code == 200:
                out.append(time.perf_counter() - started)
            time.sleep(gap)
    return out


def ws_url(url: str, path: str) -> str:
    return url.replace("http://", "ws://") + path


def drain(ws: Any, stop: threading.Event) -> None:
    try:
        while not stop.is_set():
            ws.recv(timeout=1)
    except TimeoutError:
        drain(ws, stop)
    except Exception:
        return


# ---------------------------------------------------------------- 1. rosapi flood


def rosapi_flood(url: str, pid: int) -> None:
    who = sign_in(url, "admin", PASSWORD)
    idle = rss_mib(pid)
    value = json.dumps("x" * 900_000)
    peaks, afters, refused = [], [], 0
    for round_ in range(5):
        ws = connect(
            ws_url(url, f"/rosbridge?token={who['token']}"), max_size=None, ping_interval=None
        )
        with ws:
            for n in range(100):
                args = {"name": f"/flood/r{round_}/p{n}", "value": value}
                ws.send(
                    json.dumps(
                        {
                            "op": "call_service",
                            "service": "/rosapi/set_param",
                            "args": args,
                            "id": n,
                        }
                    )
                )
            answered = 0
            while answered < 100:
                message = json.loads(ws.recv(timeout=120))
                if message.get("op") == "service_response":
                    answered += 1
                    refused += message["result"] is False
            peaks.append(rss_mib(pid))
        time.sleep(1.0)
        afters.append(rss_mib(pid))
    print(
        f"1. rosapi flood (5 rounds of 100 × 0.9 MB set_param, the socket closed after each):"
        f" RSS idle {idle:.0f} MiB, open max {max(peaks):.0f} MiB, after the last close "
        f"{afters[-1]:.0f} MiB (= {afters[-1] / idle:.2f} × idle; after each round: "
        f"{', '.join(f'{a:.0f}' for a in afters)}); {refused} of 500 refused as over the limit"
    )


# ---------------------------------------------------------------- 2. slowloris


def slowloris(url: str, connections: int, stop: threading.Event) -> None:
    port = int(url.rsplit(":", 1)[1])
    sel = selectors.DefaultSelector()

    def open_one() -> None:
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=5)
            s.sendall(b"GET /api/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
            s.setblocking(False)
            sel.register(s, selectors.EVENT_READ)
        except OSError:
            pass

    for _ in range(connections):
        open_one()
    while not stop.is_set():
        for key, _ in sel.select(0.2):
            s = key.fileobj
            assert isinstance(s, socket.socket)
            sel.unregister(s)
            s.close()
            open_one()  # reopen each one cut
        while len(sel.get_map()) < connections and not stop.is_set():
            open_one()
    for key in list(sel.get_map().values()):
        key.fileobj.close()  # type: ignore[union-attr]


def slowloris_phase(url: str, who: dict[str, str], idle: list[float]) -> None:
    stop = threading.Event()
    attacker = threading.Thread(target=slowloris, args=(url, 450, stop), daemon=True)
    attacker.start()
    time.sleep(3.0)
    ok = 0
    for _ in range(11):
        with suppress(httpx.HTTPError):
            ok += httpx.get(url + "/api/health", timeout=5).status_code == 200
        time.sleep(1.0)
    under = rest_stops(url, who, 30)
    stop.set()
    attacker.join(30)
    print(
        f"2. reconnecting slowloris (450 connections > the limit of 400): /api/health "
        f"answered {ok} of 11 probes; STOP (REST) {ms(under)} "
        f"(= {p(under, 0.95) / p(idle, 0.95):.1f} × idle p95; {30 - len(under)} refused)"
    )


# ---------------------------------------------------------------- 3. fragments


def fragments_phase(url: str, who: dict[str, str], idle: list[float]) -> None:
    student = sign_in(url, "s00")
    stop = threading.Event()
    sockets, readers = [], []
    for _ in range(8):
        ws = connect(ws_url(url, f"/rosbridge?token={student['token']}"), max_size=None)
        for topic in ("/joint_states", "/tool_pose_stamped"):
            ws.send(json.dumps({"op": "subscribe", "topic": topic, "fragment_size": 1}))
        sockets.append(ws)
        reader = threading.Thread(target=drain, args=(ws, stop), daemon=True)
        reader.start()
        readers.append(reader)
    time.sleep(2.0)
    under = rest_stops(url, who, 40)
    stop.set()
    for ws in sockets:
        ws.close()
    print(
        f"3. fragment_size 1 on 8 rosbridge sockets (2 topics each): STOP (REST) {ms(under)}"
        f" (= {statistics.median(under) / statistics.median(idle):.1f} × idle p50, "
        f"{p(under, 0.95) / p(idle, 0.95):.1f} × idle p95)"
    )


# ---------------------------------------------------------------- 4. the class


def student(url: str, n: int, until: float, results: Any) -> None:
    who = sign_in(url, f"s{n:02d}")
    headers = {k: v for k, v in who.items() if k != "token"}
    stop = threading.Event()
    with httpx.Client(base_url=url, timeout=120, headers=headers) as c:
        default = c.get("/api/workspaces").json()["default_id"]
        base = c.get(f"/api/workspaces/{default}").json()["revision"]
        ws = connect(ws_url(url, "/api/ws?target=mine"), additional_headers=headers)
        threading.Thread(target=drain, args=(ws, stop), daemon=True).start()
        body = {"program": LOOP, "points": LOOP_POINTS}
        loaded = c.post("/api/robot/project?target=mine", json=body)
        results.put(("load", loaded.status_code))
        if loaded.status_code == 200:
            c.post("/api/robot/run?target=mine", json={"servo_on": True})
        last_save = time.monotonic()
        typed = TYPING
        while time.monotonic() < until:
            typed += f"{10 * len(typed)} ' typing\n"
            c.post("/api/check", json={"program": typed[-20_000:], "points": LOOP_POINTS})
            if time.monotonic() - last_save >= 5.0:
                saved = c.put(
                    f"/api/workspaces/{default}",
                    json={"base": base, "program": typed[-20_000:], "points": LOOP_POINTS},
                )
                if saved.status_code == 200:
                    base = saved.json()["revision"]["number"]
                last_save = time.monotonic()
            time.sleep(1.0)
    stop.set()
    ws.close()


def instructor_jogs(url: str, until: float) -> None:
    who = sign_in(url, "teach")
    headers = {k: v for k, v in who.items() if k != "token"}
    with httpx.Client(base_url=url, timeout=60, headers=headers) as c:
        c.post("/api/robot/servo", json={"on": True})
    stop = threading.Event()
    with connect(ws_url(url, "/api/ws"), additional_headers=headers) as ws:
        threading.Thread(target=drain, args=(ws, stop), daemon=True).start()
        direction = 1
        while time.monotonic() < until:
            ws.send(
                json.dumps(
                    {
                        "type": "jog_start",
                        "frame": "joint",
                        "axis": 0,
                        "direction": direction,
                        "id": "j",
                    }
                )
            )
            for _ in range(20):
                ws.send(json.dumps({"type": "jog_heartbeat"}))
                time.sleep(0.1)
            ws.send(json.dumps({"type": "jog_release", "id": "r"}))
            direction = -direction
            time.sleep(0.5)
        stop.set()


def class_load(url: str, students: int, until: float, results: Any) -> None:
    """In the child process: the students and the instructor."""
    threads = [threading.Thread(target=instructor_jogs, args=(url, until), daemon=True)]
    for n in range(students):
        threads.append(threading.Thread(target=student, args=(url, n, until, results)))
    for thread in threads:
        thread.start()
        time.sleep(0.1)
    for thread in threads:
        thread.join()


def socket_stops(url: str, who: dict[str, str], until: float) -> list[float]:
    headers = {k: v for k, v in who.items() if k != "token"}
    out = []
    with connect(ws_url(url, "/api/ws"), additional_headers=headers) as ws:
        n = 0
        while time.monotonic() < until:
            n += 1
            started = time.perf_counter()
            ws.send(json.dumps({"type": "stop", "id": n}))
            while True:
                message = json.loads(ws.recv(timeout=60))
                if message.get("type") == "ack" and message.get("id") == n:
                    out.append(time.perf_counter() - started)
                    break
            time.sleep(2.0)
    return out


def class_phase(url: str, pid: int, who: dict[str, str], students: int, minutes: float) -> None:
    idle_socket = socket_stops(url, who, time.monotonic() + 10)
    idle_rest = rest_stops(url, who, 30)
    before = rss_mib(pid)
    until = time.monotonic() + 60 * minutes
    results: Any = multiprocessing.Queue()
    child = multiprocessing.Process(target=class_load, args=(url, students, until, results))
    child.start()
    memory: list[tuple[float, float]] = []
    rest: list[float] = []
    sock: list[float] = []
    loads: list[int] = []

    def sample_memory() -> None:
        while time.monotonic() < until:
            memory.append((time.monotonic(), rss_mib(pid)))
            time.sleep(5.0)

    sampler = threading.Thread(target=sample_memory, daemon=True)
    sampler.start()
    socket_thread = threading.Thread(
        target=lambda: sock.extend(socket_stops(url, who, until)), daemon=True
    )
    socket_thread.start()
    while time.monotonic() < until:
        rest.extend(rest_stops(url, who, 5, gap=1.0))
    socket_thread.join(90)
    sampler.join(10)
    child.join(300)
    while not results.empty():
        _kind, status = results.get()
        loads.append(status)
    started = memory[0][0]
    late = [(t, m) for t, m in memory if t - started >= 60.0]
    slope = (
        (late[-1][1] - late[0][1]) * 1024 / max(1.0, late[-1][0] - late[0][0])
        if len(late) > 1
        else float("nan")
    )
    refused = sum(1 for s in loads if s != 200)
    by_minute = [m for t, m in memory if int((t - started) // 60) > int((t - started - 5) // 60)]
    print(
        f"4. class of {students} students (typing, autosaving, private simulators running) and "
        f"an instructor jogging, {minutes:g} min:\n"
        f"   STOP from REST   {ms(rest)}  (idle {ms(idle_rest)}; {len(rest)} stops)\n"
        f"   STOP over socket {ms(sock)}  (idle {ms(idle_socket)}; {len(sock)} stops)\n"
        f"   REST against the socket in the same run: p50 "
        f"{statistics.median(rest) / statistics.median(sock):.2f} ×, p95 "
        f"{p(rest, 0.95) / p(sock, 0.95):.2f} ×\n"
        f"   budget 500 ms: REST p95 {'within' if p(rest, 0.95) <= 0.5 else 'OVER'}, socket "
        f"p95 {'within' if p(sock, 0.95) <= 0.5 else 'OVER'}\n"
        f"   first Load project presses refused: {refused} of {len(loads)} "
        f"(statuses {sorted(set(loads))})\n"
        f"   server memory: {before:.0f} MiB before, {memory[-1][1]:.0f} MiB at the end; after "
        f"the first minute {slope:.1f} kB/s in all = {slope / students:.2f} kB/s per running "
        f"private simulator (over {late[-1][0] - late[0][0] if len(late) > 1 else 0:.0f} s)\n"
        f"   server memory at each minute, MiB: {', '.join(f'{m:.0f}' for m in by_minute)}"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--students", type=int, default=40)
    parser.add_argument("--minutes", type=float, default=3.0)
    parser.add_argument("--only", default="1234")
    args = parser.parse_args()
    print(f"load average before: {load()} (2 cores)")
    with serve(args.students, instructors=1) as (url, pid):
        who = sign_in(url, "admin", PASSWORD)
        idle = rest_stops(url, who, 40)
        print(f"0. STOP (REST) idle: {ms(idle)}")
        phases: dict[str, Callable[[], None]] = {
            "1": lambda: rosapi_flood(url, pid),
            "2": lambda: slowloris_phase(url, who, idle),
            "3": lambda: fragments_phase(url, who, idle),
            "4": lambda: class_phase(url, pid, who, args.students, args.minutes),
        }
        for key in args.only:
            phases[key]()
            print(f"   (load average: {load()})", flush=True)


if __name__ == "__main__":
    main()
