"""Pre-flight's cost: CPU time of the thesis's 97-s pyramid program, checked in an empty
cell (the table only) and in the thesis's bench with its six blocks (parts carried and
stacked, every link and the gripper checked against the bench and the blocks), and how
many arm configurations the collision check looked at beyond the path's coarse samples.

    .venv/bin/python bench/bench_preflight.py [--runs N]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import melfa.sim.debug.preflight as pf
from melfa.sim.debug.cell import Cell
from melfa.sim.debug.cell_templates import template

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def cpu_ms(program: str, points: str, cell: Cell, runs: int) -> list[float]:
    out = []
    for _ in range(runs):
        start = time.process_time()
        pf.preflight(program, points, cell=cell)
        out.append((time.process_time() - start) * 1000)
    return sorted(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args()
    program = (EXAMPLES / "pyramid.MB4").read_text(encoding="utf-8")
    points = (EXAMPLES / "pyramid.POS").read_text(encoding="utf-8")
    bench = template("thesis-bench")
    pf.preflight(program, points, cell=bench)  # imports, caches
    for name, cell in (("empty cell", Cell()), ("thesis-bench", bench)):
        ms = cpu_ms(program, points, cell, args.runs)
        print(
            f"pyramid pre-flight, {name}: best {ms[0]:.1f} ms CPU, "
            f"median {statistics.median(ms):.1f} ms ({args.runs} runs)"
        )
    counted = {"checked": 0, "coarse": 0}
    check = pf.move_collisions

    def counting(*a: object, **kw: object) -> object:
        found, n = check(*a, **kw)  # type: ignore[arg-type]
        counted["checked"] += n
        counted["coarse"] += len(a[2])  # type: ignore[arg-type]
        return found, n

    pf.move_collisions = counting  # type: ignore[assignment]
    report = pf.preflight(program, points, cell=bench)
    pf.move_collisions = check
    moves = len({p.move for p in report.path})
    print(
        f"collision check: {counted['checked']} configurations over {moves} moves "
        f"({counted['coarse']} coarse path samples, the rest where an obstacle was within "
        f"reach: no point moves more than 5 mm between them); "
        f"{len(report.collisions)} collisions, {len(report.hands)} hand actions"
    )


if __name__ == "__main__":
    main()
