"""Sixty private simulators beside the lab robot, in one process (what `melfa serve` runs).

Each private simulator (`melfa.service.simulator.PrivateSimulator`, what a student's
"My simulator" is) runs a looping motion program in real time with one listener, as if its
owner watched it in the IDE. Measured in one run:

1. simulated time over wall time, for the slowest simulator: how far its program clock got
   in the window against the wall clock (1.00: it kept real time);
2. the lab robot's state stream (snapshots/s to one listener), with the sixty running
   against the same robot with none (0.95 or more: the lab robot did not notice them);
3. memory per simulator: the process's resident size after making them, less before,
   divided by their number.

The lab robot is the in-process virtual controller on a paced 9600-baud 8E2 line with
0.1 s controller latency (the real arm's link; ``--unpaced`` for the bare in-process one).

Run: ``.venv/bin/python bench/bench_private.py [--count 60] [--seconds 10]``.
"""

from __future__ import annotations

import argparse
import asyncio
import resource
import time
from pathlib import Path
from typing import Any

from melfa.lang.plan import plan_upload
from melfa.link import LinkSettings, PacedLink
from melfa.service import Actor, RobotService, Role, StateSnapshot, Subscription
from melfa.service.simulator import PrivateSimulator
from melfa.sim import VirtualController, open_sim_link

PROGRAM = """OVRD 100
*LOOP
MOV P1
MVS P2
MOV J1
GOTO *LOOP
"""
POINTS = [
    "DEF POS P1=(350.00,-150.00,400.00,180.00,0.00,180.00)(7,0)",
    "DEF POS P2=(350.00,150.00,300.00,180.00,0.00,180.00)(7,0)",
    "DEF JNT J1=(20.00,10.00,100.00,0.00,60.00,0.00)",
]


def rss_bytes() -> int:
    """Resident set size now (Linux: /proc/self/statm, in pages)."""
    pages = int(Path("/proc/self/statm").read_text(encoding="ascii").split()[1])
    return pages * resource.getpagesize()


def lab_service(unpaced: bool) -> RobotService:
    controller = VirtualController()
    if unpaced:
        return RobotService(lambda: open_sim_link(controller=controller))
    settings = LinkSettings(timeout=5.0)
    return RobotService(
        lambda: PacedLink(open_sim_link(settings, controller=controller), latency=0.1)
    )


async def count(sub: Subscription, seconds: float) -> float:
    """Snapshots per second one listener gets in ``seconds``."""
    got = 0
    started = time.monotonic()
    deadline = started + seconds
    while (left := deadline - time.monotonic()) > 0:
        if await sub.get_within(left) is None:
            break
        got += 1
    return got / (time.monotonic() - started)


async def drain(sub: Subscription) -> None:
    """A watching student's socket: takes every snapshot it is given."""
    while True:
        await sub.get()


def program_clock(sim: PrivateSimulator) -> float:
    """The simulator's program clock, read without advancing it."""
    with sim.lock:
        runner = sim.controller.slots[1].runner
        assert runner is not None
        now: float = runner.now  # type: ignore[attr-defined]
        return now


async def run(count_: int, seconds: float, unpaced: bool) -> dict[str, Any]:
    lab = await lab_service(unpaced).start()
    lab_sub = lab.subscribe(StateSnapshot)
    await count(lab_sub, 2.0)  # warm up: the first connection and reads
    idle_rate = await count(lab_sub, seconds)

    before = rss_bytes()
    sims = [await PrivateSimulator(f"student{i}").start() for i in range(count_)]
    watchers = []
    for i, sim in enumerate(sims):
        actor = sim.actor(Actor(f"student{i}", Role.STUDENT, "bench"))
        await sim.service.servo(actor, True)
        await sim.service.load_project(actor, plan_upload(PROGRAM, "\n".join(POINTS)))
        await sim.service.run(actor)
        watchers.append(asyncio.create_task(drain(sim.service.subscribe(StateSnapshot))))
    await asyncio.sleep(1.0)  # every program under way
    made = rss_bytes()

    clocks0 = [program_clock(s) for s in sims]
    wall0 = time.monotonic()
    busy_rate = await count(lab_sub, seconds)
    wall1 = time.monotonic()
    clocks1 = [program_clock(s) for s in sims]
    ratios = [(c1 - c0) / (wall1 - wall0) for c0, c1 in zip(clocks0, clocks1, strict=True)]
    running = sum(1 for s in sims if s.service.state.running)

    for task in watchers:
        task.cancel()
    await asyncio.gather(*watchers, return_exceptions=True)
    for sim in sims:
        await sim.close()
    lab_sub.close()
    await lab.close()
    return {
        "idle_rate": idle_rate,
        "busy_rate": busy_rate,
        "slowest": min(ratios),
        "fastest": max(ratios),
        "running": running,
        "per_sim_mb": (made - before) / count_ / 2**20,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=60, help="private simulators")
    parser.add_argument("--seconds", type=float, default=10.0, help="measuring window (s)")
    parser.add_argument("--unpaced", action="store_true", help="lab robot on a bare link")
    args = parser.parse_args()
    out = asyncio.run(run(args.count, args.seconds, args.unpaced))
    line = "bare in-process link" if args.unpaced else "9600 8E2 paced, 0.1 s latency"
    print(f"{args.count} private simulators, looping motion, {args.seconds:.0f} s window")
    print(f"programs still running at the end: {out['running']} of {args.count}")
    print(
        f"simulated time / wall time, slowest simulator: {out['slowest']:.3f} "
        f"(fastest {out['fastest']:.3f}; aim >= 0.98)"
    )
    print(
        f"lab robot ({line}) snapshots/s: {out['busy_rate']:.2f} with them, "
        f"{out['idle_rate']:.2f} without: {out['busy_rate'] / out['idle_rate']:.3f} "
        "(aim >= 0.95)"
    )
    print(f"memory per simulator: {out['per_sim_mb']:.2f} MB resident")


if __name__ == "__main__":
    main()
