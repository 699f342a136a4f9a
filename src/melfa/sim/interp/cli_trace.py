"""Run a program on the simulated RV-6S with no robot and print what it does.

The library side of ``melfa sim --run PROGRAM.MB4 [--points FILE.POS] [--fast]`` (the
command itself belongs to ``melfa.cli.sim_commands``): one line per executed step with
the simulated time, the step number, the statement, the TCP pose (mm, degrees) and the
hands; then how it ended. A run-time error shows its number, line and message.

Exit codes follow the CLI's: 0 done, 1 the program stopped with an error, 2 a file is
missing or unreadable (or the points file is broken).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import TextIO

from melfa.lang.points import PointDef, PointKind, parse_points
from melfa.sim.arm import HandState, SimulatedArm
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.fast import DEFAULT_MAX_TIME_S, run_fast
from melfa.sim.interp.interpreter import Interpreter, Step
from melfa.sim.interp.values import Joints, Position, Value
from melfa.sim.runner import RunnerStatus

REAL_TIME_TICK_S = 0.02
"""How often the real-time mode advances the program (wall-clock seconds)."""


def point_value(p: PointDef) -> Value:
    """A points-file entry as a program value (degrees in, radians inside)."""
    values = [v if v is not None else 0.0 for v in p.values]
    if p.kind is PointKind.JNT:
        return Joints.from_degrees(values)
    return Position.from_degrees(values, p.fl1 if p.fl1 is not None else 7, p.fl2 or 0)


def _hands(arm: SimulatedArm) -> str:
    marks = {HandState.OPEN: "O", HandState.CLOSED: "C", None: "-"}
    return "".join(marks[h] for h in arm.hands[:4])


def _row(t: float, line: int | None, text: str, arm: SimulatedArm) -> str:
    p = arm.pose
    shown = "" if line is None else str(line)
    return (
        f"{t:9.3f} {shown:>6} {text[:28]:<28} "
        f"{p.x:9.2f} {p.y:9.2f} {p.z:9.2f} {p.a:8.2f} {p.b:8.2f} {p.c:8.2f} {_hands(arm)}"
    )


HEADER = (
    f"{'time s':>9} {'line':>6} {'statement':<28} "
    f"{'x':>9} {'y':>9} {'z':>9} {'a':>8} {'b':>8} {'c':>8} hand"
)


def run_and_trace(
    program_path: Path,
    points_path: Path | None,
    fast: bool,
    out: TextIO,
    *,
    max_time: float = DEFAULT_MAX_TIME_S,
) -> int:
    """Run `program_path` (with the points of `points_path`) and print its trace to `out`."""
    try:
        text = Path(program_path).read_text(encoding="utf-8", errors="replace")
        points_text = (
            Path(points_path).read_text(encoding="utf-8", errors="replace") if points_path else ""
        )
    except OSError as exc:
        out.write(f"error: cannot read {exc.filename}: {exc.strerror}\n")
        return 2
    points = parse_points(points_text)
    if points.has_errors:
        for d in points.diagnostics:
            if d.is_error:
                out.write(f"{points_path}:{d.line}:{d.column}: error: {d.message}\n")
        return 2
    arm = SimulatedArm()
    it = Interpreter(ArmPort(arm))
    try:
        it.load(text)
    except errors.RunError as exc:
        out.write(f"{program_path}: cannot run: {exc}\n")
        return 1
    for p in points:
        it.set_point(p.key, point_value(p))

    def trace(step: Step) -> None:
        out.write(_row(it.now, step.number, it.step_text(step), arm) + "\n")

    out.write(HEADER + "\n")
    it.on_step = trace
    it.start(0.0, cycle=True)
    if fast:
        run_fast(it, max_time=max_time)
    else:
        t0 = time.monotonic()
        while it.status is RunnerStatus.RUNNING and it.now < max_time:
            it.advance(time.monotonic() - t0)
            time.sleep(REAL_TIME_TICK_S)
    it.on_step = None
    out.write(_row(it.now, it.line, "(end)", arm) + "\n")
    err = it.error
    if err is not None:
        out.write(f"{program_path}: {errors.describe(err)}\n")
        return 1
    if it.status is RunnerStatus.PAUSED:
        out.write(f"paused at line {it.line} (HLT)\n")
    elif it.status is RunnerStatus.RUNNING:
        out.write(f"still running at line {it.line} after {max_time:g} s (stopped)\n")
    else:
        out.write(f"finished at line {it.line} after {it.now:.3f} s\n")
    return 0
