"""Pre-flight: what a program would do to the real arm, from a simulated run.

`preflight(program, points, cell=…)` runs the program at instant speed on a fresh simulated
RV-6S (`engine.Debugger`) and `analyse` reads the run's trajectory (every move the arm
made, sampled every `Limits.sample_s`):

* the cycle time (start to END);
* every joint's closest approach to its limit (`JointMargin`), and a warning within
  `Limits.joint_margin_deg`;
* unreachable targets: a move the arm refused (the run stops there with the controller's
  error), and points of the points file it cannot take;
* the wrist singularity (J5 near 0°: J4 and J6 line up) and the shoulder singularity (the
  wrist centre near J1's axis) passed near;
* the tool (the TCP under the program's TOOL) below the cell's table plane or inside one of
  its boxes (`cell.Cell`).

The report also keeps what a grader reads of the run (`melfa.grade`): where the tool ended
(`final`), the outputs on at the end (`outputs`) and each move with its line, times and
where it ended (`moves`).

Each `Finding` carries the line of the user's text whose move caused it and the `Segment`
of the path (move index and simulated times) where it happens, so a 3D view can colour
that part of the path. Pure logic: no clock, no I/O.
"""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from melfa.kin import Pose
from melfa.kin.model import FLANGE, JOINT_LIMITS
from melfa.kin.pose import pose_to_matrix
from melfa.kin.reach import unreachable_points
from melfa.kin.solver import fk_batch
from melfa.lang.points import PointDef
from melfa.sim.debug.cell import Cell
from melfa.sim.debug.cell_collision import ArmBodies, Collision, move_collisions
from melfa.sim.debug.cell_run import CellRun
from melfa.sim.debug.cell_world import TABLE, HandAction, PartState, Snapshot
from melfa.sim.debug.engine import (
    DEFAULT_MAX_TIME_S,
    INSTANT,
    Debugger,
    ErrorReport,
    RunState,
    StopReason,
    load_points,
)
from melfa.sim.interp import errors
from melfa.sim.trajectory import MoveEvent

KINEMATIC_ERRORS = frozenset(
    {errors.JOINT_LIMIT, errors.ILLEGAL_POSITION}
    | set(range(errors.XYZ_LIMIT, errors.XYZ_LIMIT + 14))
    | set(range(errors.POSITION_LIMIT, errors.POSITION_LIMIT + 4))
    | set(range(errors.ILLEGAL_POSITION_DATA, errors.ILLEGAL_POSITION_DATA + 4))
)
"""Controller errors that mean "the arm cannot go there" (joint limit, out of range…)."""


@dataclass(frozen=True, slots=True)
class Limits:
    """How close is too close: the thresholds of the findings."""

    joint_margin_deg: float = 5.0
    wrist_deg: float = 5.0  # |J5| below this: near the wrist singularity
    shoulder_mm: float = 50.0  # wrist centre this close to J1's axis: shoulder singularity
    sample_s: float = 0.05  # trajectory sampling step (simulated seconds) …
    max_samples: int = 20  # … but at most this many per move (a linear move costs an IK each)


class Severity(enum.Enum):
    ERROR = "error"  # the real arm would stop, crash or refuse: fix before running
    WARNING = "warning"  # legal, but worth a look


class Kind(enum.Enum):
    UNREACHABLE = "unreachable"
    RUN_ERROR = "run-error"
    NOT_FINISHED = "not-finished"
    JOINT_LIMIT = "joint-limit"
    WRIST_SINGULARITY = "wrist-singularity"
    SHOULDER_SINGULARITY = "shoulder-singularity"
    BELOW_FLOOR = "below-floor"
    IN_OBSTACLE = "in-obstacle"
    COLLISION = "collision"


@dataclass(frozen=True, slots=True)
class Segment:
    """Where on the path: the `move`-th move of the run, from `start` to `end` (simulated
    seconds since the run began)."""

    move: int
    start: float
    end: float

    def to_json(self) -> dict[str, Any]:
        return {"move": self.move, "start": self.start, "end": self.end}


@dataclass(frozen=True, slots=True)
class Finding:
    kind: Kind
    severity: Severity
    message: str
    line: int | None  # line of the user's program text that caused it
    segment: Segment | None = None

    def to_json(self) -> dict[str, Any]:
        return {
            "kind": self.kind.value,
            "severity": self.severity.value,
            "message": self.message,
            "line": self.line,
            "segment": self.segment.to_json() if self.segment else None,
        }


@dataclass(frozen=True, slots=True)
class JointMargin:
    """Joint `joint`'s closest approach to a limit over the run (degrees)."""

    joint: int
    margin: float  # degrees left to the nearest limit at the closest point
    value: float  # the joint's angle there
    limit: float  # the limit it came close to
    line: int | None
    segment: Segment | None

    def to_json(self) -> dict[str, Any]:
        return {
            "joint": self.joint,
            "margin": self.margin,
            "value": self.value,
            "limit": self.limit,
            "line": self.line,
            "segment": self.segment.to_json() if self.segment else None,
        }


@dataclass(frozen=True, slots=True)
class PathPoint:
    """A sample of the tool's path for a 3D view: time, TCP position (mm), move, line."""

    time: float
    x: float
    y: float
    z: float
    move: int
    line: int | None


@dataclass(frozen=True, slots=True)
class MoveAt:
    """A move of the run: when it began and ended (simulated seconds since the start), the
    line of the user's text, and the TCP pose at its end."""

    start: float
    end: float
    line: int | None
    target: Pose


@dataclass(frozen=True, slots=True)
class Report:
    finished: bool
    cycle_time: float | None  # simulated seconds from start to END (None: it did not end)
    duration: float  # simulated seconds the run took
    joints: tuple[JointMargin, ...]
    findings: tuple[Finding, ...]
    path: tuple[PathPoint, ...] = field(default_factory=tuple)
    error: ErrorReport | None = None
    parts: tuple[PartState, ...] = field(default_factory=tuple)
    """Where each part of the cell ended (in the cell's order)."""
    hands: tuple[HandAction, ...] = field(default_factory=tuple)
    """Every close and open of the gripper's hand: time, line, pose, the part."""
    final: Pose | None = None  # the TCP pose (under TOOL and BASE) where the run ended
    outputs: dict[int, int] = field(default_factory=dict)  # output bits on at the end
    moves: tuple[MoveAt, ...] = field(default_factory=tuple)
    collisions: tuple[Collision, ...] = field(default_factory=tuple)
    """A link or the gripper inside a fixture, a part or the table (each also a finding)."""

    @property
    def ok(self) -> bool:
        """No finding of `Severity.ERROR` (what a gate before the real arm asks)."""
        return not any(f.severity is Severity.ERROR for f in self.findings)

    @property
    def errors(self) -> list[Finding]:
        return [f for f in self.findings if f.severity is Severity.ERROR]

    def to_json(self) -> dict[str, Any]:
        return {
            "ok": self.ok,
            "finished": self.finished,
            "cycle_time": self.cycle_time,
            "duration": self.duration,
            "joints": [j.to_json() for j in self.joints],
            "findings": [f.to_json() for f in self.findings],
            "path": [[p.time, p.x, p.y, p.z, p.move, p.line] for p in self.path],
            "error": self.error.to_json() if self.error else None,
            "parts": [p.to_json() for p in self.parts],
            "hands": [h.to_json() for h in self.hands],
            "collisions": [c.to_json() for c in self.collisions],
        }


def preflight(
    program: str,
    points: str | Iterable[PointDef] = "",
    *,
    cell: Cell | None = None,
    limits: Limits | None = None,
    inputs: Iterable[tuple[int, int]] = (),
    max_time: float = DEFAULT_MAX_TIME_S,
) -> Report:
    """Run `program` at instant speed on a fresh simulated arm and report on its path.

    Raises `DebugError` when the program or its points cannot be loaded at all.
    """
    point_defs = load_points(points, program)
    cell = cell if cell is not None else Cell()
    d = Debugger(program, point_defs, clock=lambda: 0.0, speed=INSTANT, max_time=max_time)
    run = CellRun.follow(cell, d)
    for bit, value in inputs:
        d.set_input(bit, value)
    d.run()
    waits = 0
    while d.state is RunState.RUNNING:
        if d.poll() is None and d.waiting:
            waits = 0 if run.world.running else waits + 1
            if waits >= 3:  # nobody will set the input it waits for
                break
    finished = d.state is RunState.FINISHED
    stop = d.last_stop
    extra: list[Finding] = []
    if stop is not None and stop.error is not None:
        kinematic = stop.error.number in KINEMATIC_ERRORS
        extra.append(
            Finding(
                Kind.UNREACHABLE if kinematic else Kind.RUN_ERROR,
                Severity.ERROR,
                f"line {stop.location.line}: the run stops here: {stop.error.text}",
                stop.location.line,
            )
        )
    elif not finished:
        loc = d.location
        if d.waiting:
            why = "waits for an input nobody sets"
        elif stop is not None and stop.reason is StopReason.BUSY:
            why = "loops without a move, DLY or WAIT (an endless loop?)"
        else:
            why = f"did not reach END within {max_time:g} s (simulated)"
        extra.append(
            Finding(
                Kind.NOT_FINISHED,
                Severity.WARNING,
                f"the run {why}; the cycle time is unknown",
                loc.line if loc else None,
            )
        )
    stopped_on = {f.line for f in extra if f.kind is Kind.UNREACHABLE}
    extra += [f for f in _unreachable_points(point_defs, d.lines) if f.line not in stopped_on]
    arm = d.arm
    report = analyse(
        arm.recorder.moves,
        line_of=d.line_of_step,
        start=d.interp.now - d.time,
        tool=arm.tool,
        base=arm.base,
        cell=cell,
        limits=limits if limits is not None else Limits(),
        loose=run.world.loose_at,
    )
    start = d.interp.now - d.time
    return Report(
        finished,
        d.time if finished else None,
        d.time,
        report.joints,
        tuple(extra) + report.findings,
        report.path,
        stop.error if stop is not None else None,
        tuple(run.parts()),
        tuple(run.actions),
        final=arm.pose,
        outputs=d.io.outputs(),
        moves=tuple(
            MoveAt(
                m.time - start,
                m.end_time - start,
                d.line_of_step(m.line),
                arm.to_pose(m.plan.end_joints),
            )
            for m in arm.recorder.moves
        ),
        collisions=report.collisions,
    )


@dataclass(frozen=True, slots=True)
class Analysis:
    joints: tuple[JointMargin, ...]
    findings: tuple[Finding, ...]
    path: tuple[PathPoint, ...]
    collisions: tuple[Collision, ...] = ()
    checked: int = 0  # samples checked for collisions (coarse and fine)


def analyse(
    moves: Sequence[MoveEvent],
    *,
    line_of: Callable[[int | None], int | None],
    start: float = 0.0,
    tool: Pose | None = None,
    base: Pose | None = None,
    cell: Cell | None = None,
    limits: Limits | None = None,
    loose: Callable[[float], Snapshot] | None = None,
) -> Analysis:
    """Findings over a run's moves (`line_of` maps a move's step number to a text line;
    `start` is the run's start on the moves' clock; `loose(t)` the parts at a time since
    the run began, loose and carried: default, the cell's parts where they start)."""
    cell = cell if cell is not None else Cell()
    limits = limits if limits is not None else Limits()
    best = [JointMargin(j + 1, math.inf, 0.0, 0.0, None, None) for j in range(6)]
    findings: list[Finding] = []
    path: list[PathPoint] = []
    bodies = ArmBodies(cell.gripper, pose_to_matrix(base) if base is not None else None)
    fixed = cell.obstacles
    collisions: list[Collision] = []
    checked = 0
    for index, move in enumerate(moves):
        end = move.plan.duration
        if index + 1 < len(moves):
            end = min(end, max(0.0, moves[index + 1].time - move.time))
        count = min(limits.max_samples, max(1, math.ceil(end / limits.sample_s)))
        ts = np.linspace(0.0, end, count + 1)
        q = move.plan.sample_many(ts)
        times = ts + (move.time - start)
        line = line_of(move.line)
        flange = fk_batch(q)
        tcp = flange @ pose_to_matrix(tool) if tool is not None else flange
        if base is not None:
            tcp = pose_to_matrix(base) @ tcp
        xyz = tcp[:, :3, 3]
        path += [
            PathPoint(float(t), float(p[0]), float(p[1]), float(p[2]), index, line)
            for t, p in zip(times, xyz, strict=True)
        ]
        _joint_margins(best, q, times, index, line)
        findings += _move_findings(index, line, q, times, flange, xyz, cell, limits)
        offset = move.time - start
        snap = loose(offset) if loose is not None else Snapshot(0.0, cell.parts, None)
        found, n = move_collisions(
            bodies,
            move.plan.sample_many,
            ts,
            q,
            tuple(fixed) + snap.loose,
            cell.floor_z,
            move=index,
            offset=offset,
            line=line,
            carried=snap.carried,
        )
        collisions += found
        checked += n
    for jm in best:
        if jm.margin < limits.joint_margin_deg:
            where = f"line {jm.line}: " if jm.line else ""
            findings.append(
                Finding(
                    Kind.JOINT_LIMIT,
                    Severity.WARNING,
                    f"{where}J{jm.joint} comes within {jm.margin:.1f}° of its limit "
                    f"{jm.limit:+g}° (J{jm.joint} = {jm.value:.1f}°)",
                    jm.line,
                    jm.segment,
                )
            )
    by_tool = list(findings)
    findings += [_collision_finding(c) for c in collisions if not _said(c, by_tool)]
    return Analysis(tuple(best), tuple(findings), tuple(path), tuple(collisions), checked)


def _said(c: Collision, findings: Sequence[Finding]) -> bool:
    """The tool's own finding on that move (below the table, inside that box) says it."""
    for f in findings:
        if f.segment is None or f.segment.move != c.move:
            continue
        if f.kind is Kind.BELOW_FLOOR and c.obstacle == TABLE:
            return True
        if f.kind is Kind.IN_OBSTACLE and f.message.endswith(f"obstacle {c.obstacle!r}"):
            return True
    return False


def _collision_finding(c: Collision) -> Finding:
    what = "the table" if c.obstacle == TABLE else repr(c.obstacle)
    body = f"the carried part {c.body!r}" if c.carried else f"the {c.body}"
    text = f"the move takes {body} {c.depth:.1f} mm into {what}"
    return Finding(
        Kind.COLLISION,
        Severity.ERROR,
        f"line {c.line}: {text}" if c.line else text,
        c.line,
        Segment(c.move, c.start, c.end),
    )


def _move_findings(
    index: int,
    line: int | None,
    q: np.ndarray,
    times: np.ndarray,
    flange: np.ndarray,
    xyz: np.ndarray,
    cell: Cell,
    limits: Limits,
) -> list[Finding]:
    """Singularities, the table and the boxes along one move's samples."""
    j5 = np.abs(q[:, 4])
    wrist = flange[:, :3, 3] - FLANGE * flange[:, :3, 2]
    from_axis = np.hypot(wrist[:, 0], wrist[:, 1])
    z = xyz[:, 2]
    checks: list[tuple[Kind, Severity, np.ndarray, Callable[[slice], str]]] = [
        (
            Kind.WRIST_SINGULARITY,
            Severity.WARNING,
            j5 < limits.wrist_deg,
            lambda r: (
                "passes near the wrist singularity "
                f"(J5 = {float(np.min(j5[r])):.1f}°: J4 and J6 line up)"
            ),
        ),
        (
            Kind.SHOULDER_SINGULARITY,
            Severity.WARNING,
            from_axis < limits.shoulder_mm,
            lambda r: (
                "passes near the shoulder singularity (the wrist comes within "
                f"{float(np.min(from_axis[r])):.0f} mm of J1's axis)"
            ),
        ),
    ]
    floor = cell.floor_z
    if floor is not None:
        checks.append(
            (
                Kind.BELOW_FLOOR,
                Severity.ERROR,
                z < floor,
                lambda r: (
                    f"takes the tool {floor - float(np.min(z[r])):.1f} mm below the "
                    f"table (Z = {float(np.min(z[r])):.1f}, the table is at {floor:g})"
                ),
            )
        )
    for box in cell.boxes:
        inside = np.all((xyz >= np.array(box.min)) & (xyz <= np.array(box.max)), axis=1)
        checks.append((Kind.IN_OBSTACLE, Severity.ERROR, inside, _saying(box.name)))
    out = []
    for kind, severity, mask, say in checks:
        for a, b in _runs(mask):
            text = say(slice(a, b))
            out.append(
                Finding(
                    kind,
                    severity,
                    f"line {line}: the move {text}" if line else f"a move {text}",
                    line,
                    Segment(index, float(times[a]), float(times[b - 1])),
                )
            )
    return out


def _saying(obstacle: str) -> Callable[[slice], str]:
    return lambda _r: f"takes the tool into the obstacle {obstacle!r}"


def _joint_margins(
    best: list[JointMargin], q: np.ndarray, times: np.ndarray, move: int, line: int | None
) -> None:
    for j, (lo, hi) in enumerate(JOINT_LIMITS):
        to_lo, to_hi = q[:, j] - lo, hi - q[:, j]
        margin = np.minimum(to_lo, to_hi)
        k = int(np.argmin(margin))
        if float(margin[k]) < best[j].margin:
            limit = lo if to_lo[k] <= to_hi[k] else hi
            t = float(times[k])
            best[j] = JointMargin(
                j + 1, float(margin[k]), float(q[k, j]), limit, line, Segment(move, t, t)
            )


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """[start, end) index ranges where `mask` holds."""
    out: list[tuple[int, int]] = []
    start: int | None = None
    for i, v in enumerate(mask.tolist()):
        if v and start is None:
            start = i
        elif not v and start is not None:
            out.append((start, i))
            start = None
    if start is not None:
        out.append((start, len(mask)))
    return out


def _unreachable_points(points: list[PointDef], lines: list[str]) -> list[Finding]:
    """Points of the points file the arm cannot take, on the first line that uses them."""
    out = []
    for name, reason in unreachable_points(points):
        pattern = re.compile(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_$])", re.I)
        line = next((i for i, text in enumerate(lines, start=1) if pattern.search(text)), None)
        if line is None:
            continue  # not used by the program
        out.append(
            Finding(Kind.UNREACHABLE, Severity.ERROR, f"line {line}: point {name} {reason}", line)
        )
    return out


def _deg(value: float) -> str:
    text = f"{value:.1f}"
    return "0.0" if text == "-0.0" else text


def report_text(report: Report, name: str = "the program") -> str:
    """The report as the command line prints it (one finding a line, errors first)."""
    out = [f"pre-flight of {name} on the simulated RV-6S"]
    if report.cycle_time is not None:
        out.append(f"cycle time: {report.cycle_time:.3f} s")
    else:
        out.append(f"cycle time: unknown (the run did not end; stopped at {report.duration:.3f} s)")
    out.append("closest approach to the joint limits:")
    for jm in report.joints:
        if math.isinf(jm.margin):
            out.append(f"  J{jm.joint}: did not move")
            continue
        where = f", line {jm.line}" if jm.line else ""
        out.append(
            f"  J{jm.joint}: {jm.margin:6.1f}° from {jm.limit:+g}° (at {_deg(jm.value)}°{where})"
        )
    if report.parts:
        out.append("where the parts ended:")
        for p in report.parts:
            x, y, z = p.position
            where = "held by the gripper" if p.held else f"on {p.on}"
            out.append(f"  {p.name}: ({x:.1f}, {y:.1f}, {z:.1f}) {where}")
    ordered = sorted(report.findings, key=lambda f: (f.severity is not Severity.ERROR, f.line or 0))
    for f in ordered:
        out.append(f"{f.severity.value}: {f.message}")
    n_err = len(report.errors)
    n_warn = len(report.findings) - n_err
    out.append(
        f"{n_err} error{'s' if n_err != 1 else ''}, {n_warn} warning{'s' if n_warn != 1 else ''}"
        + ("" if report.ok else ": fix the errors before running on the real arm")
    )
    return "\n".join(out) + "\n"
