"""Run a program on the simulated RV-6S with no robot and print what it does.

The library side of ``melfa sim --run PROGRAM.MB4 [--points FILE.POS] [--fast]`` (the
command itself is in ``melfa.cli.sim_commands``). It is meant to be read by a student at
home, so every row is one executed step *after* it ran: when it started, how long it took
(moves, DLY, WAIT), the step, the statement without its comment, where the tool ended up
(mm, degrees) and the hands. What PRINT writes appears under its step. The last lines say
how the run ended, with the simulated time and the final pose; a run-time error names the
line, shows it, and gives the controller's error number and message.

Exit codes follow the CLI's: 0 done (also paused by HLT or cut at `max_time`), 1 the program
stopped with an error or cannot run, 2 a file is missing or unreadable (or the points file
is broken).
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO

from melfa.kin import Pose
from melfa.lang.encoding import decode_file
from melfa.lang.points import PointDef
from melfa.lang.project import points_of
from melfa.protocol import POSE_NAMES
from melfa.sim.arm import SimulatedArm
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.errors import error_text
from melfa.sim.interp.fast import DEFAULT_MAX_TIME_S, run_fast
from melfa.sim.interp.interpreter import Interpreter, Step
from melfa.sim.interp.io import IOState
from melfa.sim.interp.start import RunStart
from melfa.sim.interp.values import point_value
from melfa.sim.runner import RunnerStatus
from melfa.sim.trajectory import HandState

REAL_TIME_TICK_S = 0.02
"""How often the real-time mode advances the program (wall-clock seconds)."""

SHOWN_HANDS = 4
"""Hands shown in the trace (the RV-6S has up to 8; classroom grippers use 1 or 2)."""

STATEMENT_WIDTH = 30


def strip_comment(text: str) -> str:
    """The statement without a trailing ``' comment`` (quotes inside strings are kept).

    >>> strip_comment('MDIAM = 54   \\' diameter'), strip_comment('PRINT "it\\'s"')
    ('MDIAM = 54', 'PRINT "it\\'s"')
    """
    quoted = False
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif ch == "'" and not quoted:
            return text[:i].rstrip()
    return text.rstrip()


def _fit(text: str, width: int) -> str:
    return text if len(text) <= width else text[: width - 1] + "…"


def _num(value: float) -> str:
    """Two decimals, without "-0.00" and with -180 shown as 180 (the same angle)."""
    shown = round(value, 2)
    if shown == 0 or shown == -180:
        shown = abs(shown)
    return f"{shown:.2f}"


def _hands(arm: SimulatedArm) -> str:
    marks = {HandState.OPEN: "O", HandState.CLOSED: "C", None: "-"}
    return "".join(marks[h] for h in arm.hands[:SHOWN_HANDS])


def _pose_cells(p: Pose) -> str:
    return " ".join(f"{_num(v):>8}" for v in (p.x, p.y, p.z, p.a, p.b, p.c))


HEADER = (
    f"{'time s':>9} {'took s':>7} {'line':>5}  {'statement':<{STATEMENT_WIDTH}} "
    f"{'x mm':>8} {'y mm':>8} {'z mm':>8} {'a °':>8} {'b °':>8} {'c °':>8}  hand"
)
LEGEND = (
    f"one row per step, after it ran: start time, duration, tool pose, "
    f"hands 1-{SHOWN_HANDS} (O open, C closed, - unused)"
)


def pose_summary(arm: SimulatedArm) -> str:
    """``X 400.00 Y 0.00 Z 645.00 mm, A 180.00 B 0.00 C 180.00 °, (7,0)`` for the summary."""
    p = arm.pose
    xyz = " ".join(f"{n} {_num(v)}" for n, v in zip(POSE_NAMES[:3], (p.x, p.y, p.z), strict=True))
    abc = " ".join(f"{n} {_num(v)}" for n, v in zip(POSE_NAMES[3:], (p.a, p.b, p.c), strict=True))
    return f"{xyz} mm, {abc} °, ({p.fl1},{p.fl2})"


def hands_summary(arm: SimulatedArm) -> str:
    used = [(n, h) for n, h in enumerate(arm.hands, start=1) if h is not None]
    if not used:
        return "hands not used"
    return ", ".join(f"hand {n} {h.value}" for n, h in used)


@dataclass
class _Pending:
    step: Step
    start: float
    printed: int  # PRINT lines already shown when the step started


class _Tracer:
    """Prints each step once it has finished (the next step starts, or the run ends)."""

    def __init__(self, it: Interpreter, arm: SimulatedArm, out: TextIO) -> None:
        self.it = it
        self.arm = arm
        self.out = out
        self.pending: _Pending | None = None

    def on_step(self, step: Step) -> None:
        self.flush(self.it.now)
        self.pending = _Pending(step, self.it.now, len(self.it.state.console))

    def flush(self, end: float) -> None:
        p = self.pending
        if p is None:
            return
        self.pending = None
        took = end - p.start
        took_cell = f"{took:7.3f}" if took >= 0.0005 else " " * 7
        line = "" if p.step.number is None else str(p.step.number)
        text = _fit(strip_comment(self.it.step_text(p.step)), STATEMENT_WIDTH)
        self.out.write(
            f"{p.start:9.3f} {took_cell} {line:>5}  {text:<{STATEMENT_WIDTH}} "
            f"{_pose_cells(self.arm.pose)}  {_hands(self.arm)}\n"
        )
        for printed in self.it.state.console[p.printed :]:
            self.out.write(f"{'':>25}PRINT> {printed}\n")


def _load(
    program_path: Path, points_path: Path | None, out: TextIO
) -> tuple[str, list[PointDef]] | int:
    try:
        program = decode_file(Path(program_path).read_bytes())
        given = decode_file(Path(points_path).read_bytes()) if points_path else None
    except OSError as exc:
        out.write(f"error: cannot read {exc.filename}: {exc.strerror}\n")
        return 2
    for path, decoded in ((program_path, program), (points_path, given)):
        if decoded is not None and decoded.binary_at is not None:
            out.write(f"error: {path}: not a text file (a NUL byte at line "
                      f"{decoded.binary_at[0]})\n")  # fmt: skip
            return 2
    text, points_text = program.text, given.text if given is not None else ""
    points = points_of(text, points_text)
    if points.has_errors:
        for d in points.diagnostics:
            if d.is_error:
                out.write(f"{points_path}:{d.line}:{d.column}: error: {d.message}\n")
        return 2
    return text, list(points)


def run_and_trace(
    program_path: Path,
    points_path: Path | None,
    fast: bool,
    out: TextIO,
    *,
    max_time: float = DEFAULT_MAX_TIME_S,
    inputs: Mapping[int, int] | None = None,
    start: RunStart | None = None,
) -> int:
    """Run `program_path` (with the points of `points_path`) and print its trace to `out`.

    `inputs` sets input signals (``M_IN(n)``) before the run, for programs that WAIT on
    them. `fast` jumps the simulated clock from event to event; otherwise the program runs
    in real time (Ctrl-C stops it and still prints how far it got).
    """
    loaded = _load(program_path, points_path, out)
    if isinstance(loaded, int):
        return loaded
    text, points = loaded
    io = IOState()
    for bit, value in (inputs or {}).items():
        io.set_input(bit, value)
    start = start or RunStart()
    arm = start.arm()
    it = Interpreter(ArmPort(arm), io)
    start.apply(it)
    try:
        it.load(text)
    except errors.RunError as exc:
        out.write(f"{program_path}: cannot run: {error_text(exc.to_error())}\n")
        return 1
    for p in points:
        it.set_point(p.key, point_value(p))

    tracer = _Tracer(it, arm, out)
    mode = "fast (simulated clock)" if fast else "real time"
    out.write(f"{Path(program_path).name}: running in {mode}\n{LEGEND}\n{HEADER}\n")
    it.on_step = tracer.on_step
    it.start(0.0, cycle=True)
    interrupted = False
    try:
        if fast:
            run_fast(it, max_time=max_time)
        else:
            t0 = time.monotonic()
            while it.status is RunnerStatus.RUNNING and it.now < max_time:
                it.advance(time.monotonic() - t0)
                time.sleep(REAL_TIME_TICK_S)
    except KeyboardInterrupt:
        interrupted = True
    it.on_step = None
    ended = it.state.stopped_at if it.state.stopped_at is not None else it.now
    tracer.flush(ended)
    return _summary(it, arm, out, Path(program_path), ended, max_time, interrupted)


def _summary(
    it: Interpreter,
    arm: SimulatedArm,
    out: TextIO,
    program_path: Path,
    ended: float,
    max_time: float,
    interrupted: bool,
) -> int:
    where = f"line {it.line}" if it.line is not None else "the start"
    state = f"{pose_summary(arm)}; {hands_summary(arm)}"
    err = it.error
    if err is not None:
        out.write(f"stopped by an error at {where} after {ended:.3f} s (simulated): {state}\n")
        step = it.state.steps[min(it.state.current, len(it.state.steps) - 1)]
        source = (
            it.source[step.text_line - 1].strip() if 0 < step.text_line <= len(it.source) else ""
        )
        shown = f"line {err.line}" if err.line is not None else "a line"
        out.write(f"{program_path}:{step.text_line}: error in {shown}: {error_text(err)}\n")
        if source:
            out.write(f"    {source}\n")
        return 1
    if interrupted:
        out.write(f"interrupted (Ctrl-C) at {where} after {ended:.3f} s: {state}\n")
    elif it.status is RunnerStatus.PAUSED:
        out.write(f"paused by HLT at {where} after {ended:.3f} s (simulated): {state}\n")
    elif it.status is RunnerStatus.RUNNING:
        doing = "waiting (WAIT)" if it.waiting else "still running"
        hint = "; set inputs with --input N=V" if it.waiting else ""
        out.write(f"{doing} at {where}, stopped after {max_time:g} s (simulated){hint}: {state}\n")
    else:
        out.write(f"finished at {where} after {ended:.3f} s (simulated): {state}\n")
    return 0
