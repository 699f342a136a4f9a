"""A lab session of 30 students queueing for the lab robot, time compressed.

The lab robot is `melfa sim --tcp` paced like a 9600 8E2 line with 0.1 s reply latency;
the server is melfa's web app under uvicorn (a child process started from this file, so
its queue can run on a lab clock), with the instructor's gate on. Time runs ``--scale``
times faster than in the lab, for everything at once: the queue's clock and settings
(claim 60 s, turn 240 s, warning 30 s, grace 120 s), the line (9600 × scale baud, latency
/ scale) and the students' reactions; every figure below is given back in lab seconds.

Each student signs in, keeps a socket open, passes pre-flight with a program of their own,
joins the queue and, when the arm is offered, claims it after a few (lab) seconds — every
seventh lets the first offer run out — then watches their program run and gives the arm
back. Every fifth student also tries an unsimulated text, into the queue and straight onto
the robot. An instructor probes STOP meanwhile, in turn over REST, the WebSocket and
rosbridge.

Printed: the arm's idle time between turns (a turn's end to the next run's start; goal
< 30 s of lab time), runs of unsimulated text on the robot (its bytes on the line: 0),
STOP p95 per door (budget 0.5 s, wall time; the probe runs in a process of its own),
queue update latency to every client (a join or claim sent → each socket has the message
with it; the 30 clients share one process, so their own backlog counts).

    .venv/bin/python bench/bench_queue.py [--students 30] [--scale 12]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import multiprocessing
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import websockets

sys.path.insert(0, str(Path(__file__).resolve().parent))
from serving import free_port, load, p

PASSWORD = "student-lantern-9"
POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
PROGRAM = "' student {n}\nSERVO ON\nMOV P1\nEND\n"
UNSIMULATED = "' unsim {n}\nSERVO ON\nMOV P1\nDLY 0.1\nEND\n"
PROBE_EVERY_S = 3.0
"""Wall seconds between two STOPs of the instructor's probe (each may break a turn)."""
BAUD = 9600
LATENCY_S = 0.1


# ------------------------------------------------------------------------- the server


def serve(port: int, data: Path, robot: str, scale: float) -> None:
    """The child process: melfa's app on uvicorn, its queue on a lab clock ``scale`` × fast."""
    import uvicorn
    from argon2 import PasswordHasher

    from melfa.service.clock import Clock
    from melfa.service.queue import QueueSettings
    from melfa.store import Store
    from melfa.web import WebSettings, create_app
    from melfa.web.server import uvicorn_config

    class LabClock(Clock):
        def __init__(self) -> None:
            super().__init__()
            self.t0, self.m0 = time.time(), time.monotonic()

        def now(self) -> float:
            return self.t0 + (time.monotonic() - self.m0) * scale

        async def sleep(self, seconds: float) -> None:
            await asyncio.sleep(seconds / scale)

    store = Store.open_dir(data, hasher=PasswordHasher(time_cost=1, memory_cost=64, parallelism=1))
    settings = WebSettings(
        data_dir=data,
        robot=robot,
        robot_trace=data / "robot.trace",
        require_simulation=True,
        queue=QueueSettings(),  # the defaults, in lab seconds: the clock runs scale × fast
    )
    app = create_app(settings, store=store, queue_clock=LabClock())
    config = uvicorn_config(
        app, host="127.0.0.1", port=port, limits=settings.limits, log_level="warning"
    )
    uvicorn.Server(config).run()


# ------------------------------------------------------------------------- the class

VERBOSE = False


def log(text: str) -> None:
    if VERBOSE:
        print(f"{time.monotonic():.1f} {text}", flush=True)


@dataclass
class Figures:
    stops: dict[str, list[float]] = field(
        default_factory=lambda: {"rest": [], "ws": [], "rosbridge": []}
    )
    sent_at: dict[tuple[str, str], float] = field(default_factory=dict)
    """(step kind, user) → when the request that makes it was sent."""
    seen: list[float] = field(default_factory=list)
    """Queue update latencies, every client."""
    refused_unsimulated: int = 0
    done: int = 0
    broken: int = 0
    """Turns whose load or run a STOP probe broke."""


class Person:
    def __init__(self, url: str, user: str, figures: Figures) -> None:
        self.url = url
        self.user = user
        self.figures = figures
        self.http = httpx.AsyncClient(base_url=url, timeout=120)
        self.csrf = ""
        self.ws: Any = None
        self.queue: dict[str, Any] | None = None

    async def sign_in(self, password: str) -> None:
        for _ in range(20):
            reply = await self.http.post(
                "/api/session", json={"username": self.user, "password": password}
            )
            if reply.status_code == 200:
                self.csrf = reply.json()["csrf_token"]
                return
            await asyncio.sleep(0.5)
        raise RuntimeError(f"{self.user} cannot sign in: {reply.text}")

    async def call(self, method: str, path: str, body: Any = None) -> httpx.Response:
        return await self.http.request(method, path, json=body, headers={"X-CSRF-Token": self.csrf})

    async def open(self) -> None:
        cookie = "; ".join(f"{k}={v}" for k, v in self.http.cookies.items())
        self.ws = await websockets.connect(
            self.url.replace("http", "ws") + "/api/ws",
            additional_headers={"Cookie": cookie},
            max_size=None,
        )

    def note(self, message: dict[str, Any]) -> None:
        now = time.monotonic()
        for step in message.get("steps", []):
            sent = self.figures.sent_at.get((step["kind"], step.get("user") or ""))
            if sent is not None:
                self.figures.seen.append(now - sent)
        self.queue = message


async def student(
    person: Person, n: int, scale: float, figures: Figures, ready: asyncio.Event
) -> None:
    await person.sign_in(PASSWORD)
    await person.open()
    program = PROGRAM.format(n=n)
    passed = await person.call("POST", "/api/preflight", {"program": program, "points": POINTS})
    assert passed.status_code == 200 and passed.json()["passed"], f"{person.user}: {passed.text}"
    if n % 5 == 0:  # an unsimulated text: refused into the queue, refused onto the robot
        text = UNSIMULATED.format(n=n)
        tried = await person.call("POST", "/api/queue", {"program": text, "points": POINTS})
        direct = await person.call(
            "POST", "/api/robot/project", {"program": text, "points": POINTS}
        )
        figures.refused_unsimulated += (tried.status_code == 409) + (
            direct.status_code in (409, 423)
        )
    await ready.wait()
    figures.sent_at[("joined", person.user)] = time.monotonic()
    joined = await person.call("POST", "/api/queue", {"program": program, "points": POINTS})
    assert joined.status_code == 200, joined.text
    log(f"{person.user} joined")
    missed_once = n % 7 != 0
    claimed = False
    ran = False
    async for text in person.ws:
        message = json.loads(text)
        kind = message.get("type")
        if kind == "queue":
            person.note(message)
            mine = next((e for e in message["entries"] if e["user"] == person.user), None)
            if mine is not None and mine["state"] == "offered" and not claimed:
                if not missed_once:
                    missed_once = True  # let this window run out
                    continue
                await asyncio.sleep((2 + n % 5) / scale)  # a student's reaction, lab seconds
                claimed = True
                figures.sent_at[("claimed", person.user)] = time.monotonic()
                reply = await person.call("POST", "/api/queue/claim", {"start": True})
                log(f"{person.user} claims: {reply.status_code}")
            ended = {"finished", "ended", "stopped", "gone", "skipped"}
            if claimed and any(
                st["kind"] in ended and st.get("user") == person.user for st in message["steps"]
            ):
                break  # my turn is over
        elif (
            kind == "result" and claimed and (message.get("actor") or {}).get("user") == person.user
        ):
            if message["command"] == "run" and message["ok"]:
                ran = True  # my program started: give the arm back once it has ended
            elif not message["ok"]:  # a STOP (the probes) broke my load or run: I give up
                figures.broken += 1
                await person.call("POST", "/api/queue/done")
        elif (
            kind == "state"
            and ran
            and not (message.get("program_running") or message.get("running"))
        ):
            await asyncio.sleep(3 / scale)  # look at the arm, then give it back
            await person.call("POST", "/api/queue/done")
            log(f"{person.user} done")
            ran = False
    figures.done += 1
    await person.ws.close()
    await person.http.aclose()


def probe_process(url: str, stop: Any, out: Any) -> None:
    """The STOP probe in a process of its own (the 30 students' client would delay it):
    sends its figures through ``out`` once ``stop`` is set."""
    figures = Figures()

    async def run() -> None:
        done = asyncio.Event()

        async def watch() -> None:
            while not stop.is_set():
                await asyncio.sleep(0.2)
            done.set()

        watcher = asyncio.create_task(watch())
        await prober(url, figures, done)
        await watcher

    asyncio.run(run())
    out.send(figures.stops)


async def prober(url: str, figures: Figures, stop: asyncio.Event) -> None:
    """The instructor presses STOP now and then, in turn from every door."""
    ivy = Person(url, "ivy", figures)
    await ivy.sign_in(PASSWORD)
    await ivy.open()
    token = (await ivy.call("POST", "/api/tokens", {"label": "bench"})).json()["token"]
    bridge = await websockets.connect(url.replace("http", "ws") + f"/rosbridge?token={token}")

    async def drain() -> None:
        async for _ in ivy.ws:
            pass

    drainer = asyncio.create_task(drain())
    doors = ["rest", "ws", "rosbridge"]
    i = 0
    try:
        while not stop.is_set():
            await asyncio.sleep(PROBE_EVERY_S)
            door = doors[i % 3]
            i += 1
            start = time.monotonic()
            if door == "rest":
                reply = await ivy.call("POST", "/api/robot/stop")
                assert reply.status_code == 200, reply.text
            elif door == "ws":
                probe = Person(url, "ivy", figures)  # a socket of its own: replies in order
                probe.http.cookies = ivy.http.cookies
                await probe.open()
                start = time.monotonic()
                await probe.ws.send(json.dumps({"type": "stop", "id": i}))
                async for text in probe.ws:
                    if json.loads(text).get("id") == i:
                        break
                await probe.ws.close()
            else:
                await bridge.send(
                    json.dumps(
                        {"op": "call_service", "service": "/melfa/stop", "id": f"s{i}", "args": {}}
                    )
                )
                async for text in bridge:
                    if json.loads(text).get("id") == f"s{i}":
                        break
            figures.stops[door].append(time.monotonic() - start)
    finally:
        drainer.cancel()
        await bridge.close()
        await ivy.ws.close()


def audit(data: Path) -> list[tuple[float, str, str | None, str]]:
    """(time, action, actor, result) of the session, oldest first."""
    import sqlite3

    from melfa.store.timeutil import from_text

    with sqlite3.connect(data / "melfa.sqlite3") as conn:
        rows = conn.execute("SELECT at, action, actor, result FROM audit ORDER BY id").fetchall()
    return sorted(
        (from_text(at).timestamp(), action, actor, result) for at, action, actor, result in rows
    )


def idle_between_turns(
    entries: list[tuple[float, str, str | None, str]],
) -> list[tuple[float, bool]]:
    """From each turn's end to the next run that started (wall seconds), and whether a
    claim was missed in between (the claim window ran out: idle by the rules)."""
    ends = ("queue.finished", "queue.ended", "queue.stopped", "queue.gone", "queue.skipped")
    out = []
    pending: float | None = None
    missed = False
    for at, action, _, result in entries:
        if action in ends:
            pending, missed = at, False
        elif action == "queue.missed":
            missed = True
        elif action == "robot.run" and result == "accepted" and pending is not None:
            out.append((at - pending, missed))
            pending = None
    return out


async def session(url: str, students: int, scale: float, figures: Figures) -> None:
    ready = asyncio.Event()
    people = [Person(url, f"s{n:02d}", figures) for n in range(1, students + 1)]
    stop = multiprocessing.Event()
    mine, theirs = multiprocessing.Pipe()
    probing = multiprocessing.Process(target=probe_process, args=(url, stop, theirs))
    probing.start()
    tasks = [
        asyncio.create_task(student(person, n, scale, figures, ready))
        for n, person in enumerate(people, 1)
    ]
    await asyncio.sleep(3)  # everyone signed in and passed pre-flight
    ready.set()
    try:
        async with asyncio.timeout(students * 300 / scale + 120):
            await asyncio.gather(*tasks)
    except TimeoutError:
        print(f"not every student finished: {figures.done} of {students}")
    stop.set()
    figures.stops = await asyncio.to_thread(mine.recv)
    probing.join(30)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--students", type=int, default=30)
    parser.add_argument(
        "--scale",
        type=int,
        default=12,
        choices=(1, 2, 4, 6, 12),
        help="9600 × scale is a line rate",
    )
    parser.add_argument(
        "--serve", nargs=4, metavar=("PORT", "DATA", "ROBOT", "SCALE"), help=argparse.SUPPRESS
    )
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    global VERBOSE
    VERBOSE = args.verbose
    if args.serve:
        port, data, robot, scale = args.serve
        serve(int(port), Path(data), robot, float(scale))
        return
    scale = args.scale
    data = Path(tempfile.mkdtemp(prefix="bench-queue-"))
    from argon2 import PasswordHasher

    from melfa.store import Store

    with Store.open_dir(
        data, hasher=PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)
    ) as store:
        store.accounts.create_user("ivy", PASSWORD, role="instructor")
        for n in range(1, args.students + 1):
            store.accounts.create_user(f"s{n:02d}", PASSWORD)
    sim_port, port = free_port(), free_port()
    sim = subprocess.Popen(
        [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{sim_port}",
         "--baud", str(int(BAUD * scale)), "--latency", str(LATENCY_S / scale)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )  # fmt: skip
    server = subprocess.Popen(
        [
            sys.executable,
            __file__,
            "--serve",
            str(port),
            str(data),
            f"tcp://127.0.0.1:{sim_port}",
            str(scale),
        ],
        stderr=(data / "serve.log").open("w"),
    )
    url = f"http://127.0.0.1:{port}"
    figures = Figures()
    try:
        for _ in range(200):
            try:
                if httpx.get(url + "/api/health", timeout=2).json()["robot"]["link"] == "connected":
                    break
            except (httpx.HTTPError, KeyError, ValueError):
                pass
            time.sleep(0.2)
        else:
            raise SystemExit(f"the server did not come up: {(data / 'serve.log').read_text()}")
        started = time.monotonic()
        asyncio.run(session(url, args.students, scale, figures))
        took = time.monotonic() - started
    finally:
        for process in (server, sim):
            process.send_signal(signal.SIGINT)
            try:
                process.wait(15)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
    from melfa.link.wrappers import load_trace

    sent = b"".join(
        e.data
        for e in load_trace((data / "robot.trace").read_text(encoding="utf-8").splitlines())
        if e.direction == "->"
    )
    entries = audit(data)
    handovers = [(s * scale, missed) for s, missed in idle_between_turns(entries)]
    idle = [s for s, _ in handovers]
    claimed_at_once = [s for s, missed in handovers if not missed]
    turns = sum(1 for _, a, _, r in entries if a == "queue.claimed")
    missed = sum(1 for _, a, _, r in entries if a == "queue.missed")
    say = print
    lab_min = took * scale / 60
    say(f"{args.students} students, time × {scale}: {took:.0f} s wall = {lab_min:.1f} min of lab")
    say(f"machine load {load()}")
    say(
        f"turns claimed {turns}, missed claims {missed}, students done {figures.done}, "
        f"turns broken by a STOP probe {figures.broken}"
    )
    if idle:
        median, worst = statistics.median(idle), max(idle)
        say(f"arm idle between turns (lab s): median {median:.1f}, worst {worst:.1f}")
        say(f"  over {len(idle)} hand-overs (goal < 30 s)")
    if claimed_at_once:
        median, worst = statistics.median(claimed_at_once), max(claimed_at_once)
        say(f"  where the first offer was claimed: median {median:.1f}, worst {worst:.1f}")
        say(f"  ({len(claimed_at_once)}; the others waited out a missed claim window of 60 s)")
    unsimulated = sent.count(b"unsim")
    say(f"runs of unsimulated text: {unsimulated} (its bytes on the line)")
    say(f"  refusals of it (queue, straight onto the robot): {figures.refused_unsimulated}")
    for door, values in figures.stops.items():
        if values:
            say(f"STOP {door:9s}: {quantiles(values)} over {len(values)} (budget 500 ms)")
    if figures.seen:
        say(f"queue update to every client: {quantiles(figures.seen)}")
        say(f"  max {max(figures.seen) * 1000:.0f} ms over {len(figures.seen)} deliveries")


def quantiles(values: list[float]) -> str:
    return f"p50 {statistics.median(values) * 1000:.0f} ms, p95 {p(values, 0.95) * 1000:.0f} ms"


if __name__ == "__main__":
    main()
