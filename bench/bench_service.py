"""Service figures on a paced 9600-baud 8E2 link (in-memory virtual controller + PacedLink).

1. Joint-state rate delivered to 50 subscribers, against the line-rate bound of JPOSF alone
   (request + reply characters × 1.25 ms + controller latency, protocol.md §6.1).
2. Stop latency during an upload: from `service.stop()` to STOP reaching the controller,
   against one full EMDAT's wire time (what a stop may have to wait behind).
3. Jog stop after the last heartbeat, in the virtual controller's time: from the last
   heartbeat to the arm standing still, against the controller watchdog (140 ms) plus one
   JOG round trip.

Run: ``.venv/bin/python bench/bench_service.py [--latency 0.1] [--seconds 5]``.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import threading
import time
from collections.abc import Callable
from typing import Any

from melfa.lang.plan import plan_upload
from melfa.link import Link, LinkSettings, PacedLink
from melfa.protocol import JOG_WATCHDOG_S, Request
from melfa.service import Actor, RobotService, Role, ServiceConfig, StateSnapshot, UploadProgress
from melfa.sim import VirtualController, open_sim_link
from melfa.sim.machine import SimArm

ANN = Actor("ann", Role.STUDENT, "bench")
SETTINGS = LinkSettings(timeout=5.0)
CHAR_S = SETTINGS.seconds_per_char


class Recording(VirtualController):
    def __init__(self) -> None:
        super().__init__()
        self.seen: list[tuple[float, float, str]] = []
        self._lock = threading.Lock()

    def handle(self, request: bytes | str, now: float) -> bytes:
        text = request.decode("latin-1") if isinstance(request, bytes) else request
        with self._lock:
            self.seen.append((now, time.monotonic(), text))
        return super().handle(request, now)


def paced(controller: VirtualController, latency: float) -> Link:
    inner = open_sim_link(SETTINGS, controller=controller)
    try:
        return PacedLink(inner, latency=latency)  # type: ignore[call-arg,unused-ignore]
    except TypeError:  # an older PacedLink without controller latency
        return PacedLink(inner)


def _factory(controller: VirtualController, latency: float) -> Callable[[], Link]:
    return lambda: paced(controller, latency)


def jposf_bound(latency: float) -> float:
    """Shortest JPOSF round trip: its request and reply on the wire, plus latency."""
    controller = VirtualController()
    controller.handle(b"1;1;OPEN=BENCH", 0.0)
    reply = controller.handle(b"1;1;JPOSF", 0.0)
    chars = len(Request("JPOSF").to_bytes()) + len(reply)
    return chars * CHAR_S + latency


async def stream_rate(latency: float, seconds: float) -> dict[str, Any]:
    controller = Recording()
    service = RobotService(lambda: paced(controller, latency), config=ServiceConfig())
    async with service:
        subs = [service.subscribe(StateSnapshot) for _ in range(50)]
        counts = [0] * len(subs)
        joints_seen = [0] * len(subs)

        async def read(index: int) -> None:
            last = None
            async for event in subs[index]:
                assert isinstance(event, StateSnapshot)
                counts[index] += 1
                if event.joints is not None and event.seq != last:
                    joints_seen[index] += 1
                last = event.seq

        before = len(controller.seen)
        started = time.monotonic()
        readers = [asyncio.create_task(read(i)) for i in range(len(subs))]
        await asyncio.sleep(seconds)
        elapsed = time.monotonic() - started
        window = controller.seen[before:]
        for task in readers:
            task.cancel()
        await asyncio.gather(*readers, return_exceptions=True)
    jposf = sum(1 for _, _, c in window if c.endswith("JPOSF"))
    return {
        "jposf_per_s": jposf / elapsed,
        "snapshots_per_s_min": min(counts) / elapsed,
        "snapshots_per_s_max": max(counts) / elapsed,
        "requests_per_s": len(window) / elapsed,
    }


async def stop_latency(latency: float, runs: int) -> list[float]:
    out = []
    program = "\n".join(f"{10 * i} MOV P{i % 9 + 1}" for i in range(1, 200))
    for _ in range(runs):
        controller = Recording()
        service = RobotService(_factory(controller, latency), config=ServiceConfig(polling=False))
        async with service:
            progress = service.subscribe(UploadProgress)
            upload = asyncio.create_task(service.upload_program(ANN, plan_upload(program)))
            while True:
                event = await progress.get()
                assert isinstance(event, UploadProgress)
                if event.sent > 0:
                    break
            await asyncio.sleep(0.05)  # somewhere inside a chunk
            asked = time.monotonic()
            await service.stop(ANN)
            await asyncio.gather(upload, return_exceptions=True)
        arrived = next(w for _, w, c in controller.seen if c.endswith(";STOP"))
        out.append(arrived - asked)
    return out


async def jog_stop(latency: float, runs: int) -> tuple[list[float], float]:
    out = []
    for _ in range(runs):
        controller = Recording()
        service = RobotService(_factory(controller, latency), config=ServiceConfig())
        async with service:
            await service.servo(ANN, True)
            await service.jog_start(ANN, "joint", "J1", +1)
            for _ in range(10):
                await asyncio.sleep(0.09)
                service.jog_heartbeat(ANN)
            last_heartbeat = time.monotonic()
            await asyncio.sleep(0.8)
            await service.read_joints(ANN)  # bring the controller's clock past the stop
        now0, wall0, _ = controller.seen[0]
        offset = wall0 - now0
        arm = controller.arm
        assert isinstance(arm, SimArm)
        samples = arm.arm.recorder.samples
        final = samples[-1].joints
        still_from = max(s.time for s in samples if s.joints != final)
        out.append(still_from - (last_heartbeat - offset))
    jog_rtt = (22 + 4) * CHAR_S + latency
    return out, jog_rtt


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--latency", type=float, default=0.1, help="controller latency (s)")
    parser.add_argument("--seconds", type=float, default=5.0, help="streaming window (s)")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()

    bound = jposf_bound(args.latency)
    stream = asyncio.run(stream_rate(args.latency, args.seconds))
    stops = asyncio.run(stop_latency(args.latency, args.runs))
    jogs, jog_rtt = asyncio.run(jog_stop(args.latency, args.runs))
    emdat_wire = 256 * CHAR_S

    print(f"9600 8E2 paced in-memory link, controller latency {args.latency * 1000:.0f} ms")
    print(f"{'figure':52} {'measured':>10} {'bound':>10} {'ratio':>7}")
    rows = [
        ("JPOSF reads/s while 50 subscribers listen", stream["jposf_per_s"], 1 / bound),
        (
            "snapshots/s delivered to the slowest of 50",
            stream["snapshots_per_s_min"],
            stream["requests_per_s"],
        ),
        ("stop latency during upload, median (s)", statistics.median(stops), emdat_wire),
        ("stop latency during upload, worst (s)", max(stops), emdat_wire),
        (
            "jog: last heartbeat -> arm still, median (s)",
            statistics.median(jogs),
            JOG_WATCHDOG_S + jog_rtt,
        ),
        ("jog: last heartbeat -> arm still, worst (s)", max(jogs), JOG_WATCHDOG_S + jog_rtt),
    ]
    for name, measured, ref in rows:
        print(f"{name:52} {measured:10.3f} {ref:10.3f} {measured / ref:7.2f}")
    print(
        "bounds: JPOSF-only line rate; every poll request (JPOSF, PPOSF, STATE, HNDSTS) "
        "gives one snapshot; one full EMDAT on the wire; watchdog + one JOG round trip"
    )


if __name__ == "__main__":
    main()
