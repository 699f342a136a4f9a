"""Grading speed: a class's pyramid submissions graded on this machine, and one check.

1. 40 pyramid-sized submissions (the thesis's exercise, examples/assignments/pyramid: the
   reference solution and its five typical wrong ones, in turn (7 references), each student
   with their own variant seed) graded as `melfa grade` grades them, in one process and in
   worker processes (one per core), against the issue's goal of 10 s;
2. one check of one submission (what *Check my solution* asks of the engine): the median
   wall and CPU time of `grade()` on the reference solution, over several runs.

    .venv/bin/python bench/bench_grade.py
"""

from __future__ import annotations

import os
import statistics
import time
from pathlib import Path

from melfa.cli.grade_commands import grade_all
from melfa.grade import (
    Assignment,
    Submission,
    grade,
    load_assignment,
    read_folder,
    variant_points,
)

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "assignments"
SOLUTIONS = EXAMPLE / "pyramid-solutions"
PROGRAMS = [
    "reference.MB4",
    *(f"wrong/{n}.MB4" for n in ("order", "high", "table", "no-hopen", "goto")),
]
CLASS = 40
GOAL_S = 10.0


def submissions(assignment: Assignment) -> list[tuple[Submission, str]]:
    """Student i: seed str(i), their variant's points, one of the six programs in turn."""
    texts = [(SOLUTIONS / p).read_text(encoding="utf-8") for p in PROGRAMS]
    out = []
    for i in range(CLASS):
        seed = str(i)
        points = variant_points(assignment, assignment.variant(seed))
        out.append((Submission(texts[i % len(texts)], points), seed))
    return out


def _cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def main() -> None:
    assignment = load_assignment(read_folder(EXAMPLE / "pyramid"))
    items = submissions(assignment)
    cores = os.cpu_count() or 1
    print(f"{CLASS} pyramid submissions, {len(assignment.spec.checks)} checks each, {cores} cores")
    for jobs in (1, cores):
        # every student has their own variant: the seed is the student's number here
        t0, c0 = time.perf_counter(), _cpu()
        load = os.getloadavg()[0]
        reports = grade_all(assignment, items, jobs)
        wall = time.perf_counter() - t0
        cpu = _cpu() - c0  # this process and its finished worker processes
        passed = sum(r.passed for r in reports)
        print(
            f"  {jobs} process{'es' if jobs > 1 else ''}: {wall:.2f} s wall "
            f"({wall / GOAL_S:.2f} × the {GOAL_S:g} s goal), CPU {cpu:.2f} s "
            f"({cpu / CLASS * 1000:.0f} ms per submission; {cpu / jobs / GOAL_S:.2f} × the goal "
            f"on {jobs} idle core{'s' if jobs > 1 else ''}); {passed} passed; load {load:.1f}"
        )
    walls, cpus = [], []
    reference, seed = items[0]
    for _ in range(9):
        t0, c0 = time.perf_counter(), time.process_time()
        grade(assignment, reference, seed)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    print(
        f"one check of the reference solution: median {statistics.median(walls) * 1000:.0f} ms "
        f"wall, {statistics.median(cpus) * 1000:.0f} ms CPU (min {min(walls) * 1000:.0f}, "
        f"max {max(walls) * 1000:.0f} ms wall; load average {os.getloadavg()[0]:.1f})"
    )


if __name__ == "__main__":
    main()
