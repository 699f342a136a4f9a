"""Recorded runs: how many bytes a run takes in the store, against the 1 MB budget for a
2-minute run at the line's poll rate (issue 22).

The thesis's pyramid (examples/pyramid.MB4, about 98 s at 100 %) runs on the virtual lab
robot through the real service and its recorder, on a `FakeClock` (time compressed: the
minutes pass in seconds), over

1. a paced 9600 8E2 link with 0.1 s controller latency (the real arm's line), and
2. the bare in-memory link (the service's fastest polling while a program runs: one poll
   per `ServiceConfig.running_spacing_s`).

For each it prints the frames recorded, the poll rate, the encoded size
(`melfa.service.recording_frames.encode`) and that size scaled to 2 minutes, against
1 MB, and the report against the pyramid's pre-flight: the largest TCP deviation (aligned by
line) and the cycle times, with the CPU time the comparison took. Then a worst case no line
reaches: 2 minutes of frames at 100 samples per second, every value changing each sample.

Run: ``.venv/bin/python bench/bench_runs.py``.
"""

from __future__ import annotations

import asyncio
import math
import sys
import time
from pathlib import Path

from melfa.lang.plan import plan_upload
from melfa.link import Link, LinkSettings, PacedLink
from melfa.service import Actor, RobotService, Role, ServiceConfig, ServoPolicy
from melfa.service.clock import FakeClock
from melfa.service.recording import Recording
from melfa.service.recording_compare import compare, simulated_run
from melfa.service.recording_frames import Frame, decode, encode
from melfa.sim import VirtualController, open_sim_link
from melfa.sim.debug.preflight import preflight

ROOT = Path(__file__).resolve().parents[1]
ANN = Actor("ann", Role.STUDENT, "bench")
BUDGET = 1_000_000
TWO_MINUTES = 120.0


def record(paced: bool) -> Recording:
    clock = FakeClock()
    controller = VirtualController()
    done: list[Recording] = []

    def link() -> Link:
        inner = open_sim_link(LinkSettings(timeout=5.0), controller=controller, clock=clock.now)
        if not paced:
            return inner
        return PacedLink(inner, now=clock.now, sleep=clock.pause, latency=0.1)

    async def main() -> None:
        async with clock.running():
            service = RobotService(link, config=ServiceConfig(), clock=clock)
            service.record_runs(done.append)
            async with service:
                program = (ROOT / "examples/pyramid.MB4").read_text(encoding="utf-8")
                points = (ROOT / "examples/pyramid.POS").read_text(encoding="utf-8")
                await service.load_project(ANN, plan_upload(program, points))
                await service.run(ANN, servo=ServoPolicy.TURN_ON)
                while not done:
                    await clock.sleep(1.0)

    asyncio.run(main())
    return done[0]


def worst_case() -> int:
    frames = []
    for i in range(int(TWO_MINUTES * 100)):
        t = i / 100
        joints = tuple(round(90 * math.sin(t / (2 + k)) + 0.37 * i % 1, 2) for k in range(6))
        pose = tuple(round(400 * math.cos(t / (3 + k)), 2) for k in range(6))
        frames.append(Frame(t, joints, pose, line=1 + i // 50 % 60, step=10, override=100))
    data = encode(frames)
    assert decode(data) == frames
    return len(data)


def main() -> None:
    program = (ROOT / "examples/pyramid.MB4").read_text(encoding="utf-8")
    points = (ROOT / "examples/pyramid.POS").read_text(encoding="utf-8")
    report = preflight(program, points)
    sim = simulated_run(((p.time, p.x, p.y, p.z, p.line) for p in report.path), report.cycle_time)
    for name, paced in (("paced 9600 8E2 + 0.1 s latency", True), ("bare in-memory link", False)):
        rec = record(paced)
        data = encode(rec.frames)
        rate = len(rec.frames) / rec.duration
        per_two = len(data) * TWO_MINUTES / rec.duration
        print(
            f"{name}: {rec.outcome} after {rec.duration:.1f} s, {len(rec.frames)} frames "
            f"({rate:.2f}/s), {len(data):,} bytes ({len(data) / len(rec.frames):.1f} per "
            f"frame); 2 minutes: {per_two / 1000:.1f} kB = {per_two / BUDGET:.3f} × the 1 MB budget"
        )
        started = time.process_time()
        result = compare(rec.frames, sim, rec.cycle_time)
        cpu = time.process_time() - started
        d = result.largest
        where = f"{d.mm:.1f} mm at line {d.line}" if d is not None else "none"
        print(
            f"  against pre-flight ({len(sim.path)} path samples): largest deviation {where} "
            f"over {result.compared} frames; cycle {rec.cycle_time:.2f} s real vs "
            f"{sim.cycle_time:.2f} s simulated; compared in {cpu * 1000:.0f} ms CPU"
        )
    worst = worst_case()
    print(
        f"worst case, 12,000 frames (100/s for 2 minutes, every value changing): "
        f"{worst:,} bytes = {worst / BUDGET:.3f} × the 1 MB budget"
    )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
