"""Interpreter speed: simulated time over wall time, and statements per second.

Runs in fast mode (the clock jumps to each event) on the simulated RV-6S:

1. a 1,000-line program that loops: 980 lines of arithmetic and a few moves, run 3 times
   round by a counter, so simulated motion time vs the wall time it took to compute;
2. a tight loop with no motion, for raw statement dispatch speed.

    .venv/bin/python bench/bench_interp.py
"""

from __future__ import annotations

import time

from melfa.sim.arm import SimulatedArm
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.fast import run_fast
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.runner import RunnerStatus

POINTS = ["P1=(400,-100,400,180,0,180)(7,0)", "P2=(400,100,450,180,0,180)(7,0)"]


def thousand_lines() -> str:
    """1,000 numbered lines: setup, 980 statements of work and moves, a counted loop."""
    lines = ["SERVO ON", "OVRD 100", "MC = 0", "*TOP", "M1 = 0"]
    body = 1000 - len(lines) - 4
    for i in range(body):
        if i % 100 == 50:
            lines.append("MOV P1" if (i // 100) % 2 == 0 else "MVS P2")
        elif i % 3 == 0:
            lines.append(f"M1 = M1 + {i % 7} * 2")
        elif i % 3 == 1:
            lines.append(f"IF M1 > {i} THEN M2 = M1 MOD 13 ELSE M2 = {i}")
        else:
            lines.append("P3 = P1 + (M2, 0, 0, 0, 0, 0)")
    lines += ["MC = MC + 1", "IF MC < 3 THEN *TOP", "MOV P1", "END"]
    assert len(lines) == 1000
    return "".join(f"{10 * (n + 1)} {text}\n" for n, text in enumerate(lines))


def tight_loop(n: int) -> str:
    return (
        f"10 M1 = 0\n20 FOR I = 1 TO {n}\n30 M1 = M1 + I * 2\n"
        "40 IF M1 > 100000 THEN M1 = 0\n50 NEXT I\n60 END\n"
    )


def measure(text: str, points: list[str]) -> tuple[float, float, int]:
    """(simulated seconds, wall seconds, statements executed)."""
    it = Interpreter(ArmPort(SimulatedArm()))
    count = [0]

    def tick(_step: object) -> None:
        count[0] += 1

    it.load(text, points)
    it.on_step = tick
    it.start(0.0)
    t0 = time.perf_counter()
    run_fast(it)
    wall = time.perf_counter() - t0
    assert it.status is RunnerStatus.FINISHED, it.error
    return it.now, wall, count[0]


def dispatch_rate(n: int) -> tuple[float, int]:
    """Statements per second with no tracing hook (the controller's configuration)."""
    it = Interpreter(ArmPort(SimulatedArm()), max_statements=10**9)
    it.load(tight_loop(n))
    it.start(0.0)
    t0 = time.perf_counter()
    run_fast(it)
    wall = time.perf_counter() - t0
    statements = 2 + 3 * n + 1  # FOR body (3 lines) n times, plus setup and END
    return statements / wall, statements


def main() -> None:
    sim, wall, count = measure(thousand_lines(), POINTS)
    rate, n = dispatch_rate(200_000)
    rows = [
        ("1,000-line looping program (fast mode)", ""),
        ("  statements executed", f"{count:,}"),
        ("  simulated time", f"{sim:.2f} s"),
        ("  wall time", f"{wall * 1000:.1f} ms"),
        ("  simulated / wall", f"{sim / wall:,.0f} x"),
        ("Tight loop, no motion", ""),
        ("  statements", f"{n:,}"),
        ("  statements per second", f"{rate:,.0f}"),
    ]
    width = max(len(r[0]) for r in rows)
    for label, value in rows:
        print(f"{label:<{width}}  {value:>14}")


if __name__ == "__main__":
    main()
