"""Each kind of check, judged on a simulated run (`melfa.sim.debug.preflight.Report`) or on
the program's tree, as an `Outcome`: passed, the student's message, the line that caused a
failure where there is one. Pure: the run and the tree in, the outcome out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from melfa.grade.model import (
    Avoids,
    CycleTime,
    FinalPose,
    Hand,
    HandAction,
    Io,
    PartAt,
    Uses,
    Visits,
)
from melfa.grade.statements import lines_setting_output, lines_using, normalise
from melfa.kin import Pose
from melfa.kin.pose import pose_distance
from melfa.lang import ast as A  # noqa: N812
from melfa.sim.debug.cell_world import HandAction as Action
from melfa.sim.debug.cell_world import HandChange
from melfa.sim.debug.preflight import Report as Run
from melfa.sim.debug.preflight import Severity


@dataclass(frozen=True, slots=True)
class Outcome:
    passed: bool
    message: str
    line: int | None = None


def number_text(value: float) -> str:
    """``380`` for 380.0, ``380.5`` for 380.5, never ``-0``: positions as people write them."""
    text = f"{value:.1f}".removesuffix(".0")
    return "0" if text == "-0" else text


def xyz_text(values: Sequence[float]) -> str:
    return "(" + ", ".join(number_text(v) for v in values[:3]) + ")"


def _last_move_line(run: Run) -> int | None:
    return run.moves[-1].line if run.moves else None


def final_pose(check: FinalPose, run: Run) -> Outcome:
    end = run.final
    if end is None:
        return Outcome(False, "the run has no final pose")
    want = Pose(*check.pose) if len(check.pose) == 6 else None
    if want is not None:
        dist, angle = pose_distance(end, want)
    else:
        dist, angle = math.dist(end.xyz, check.pose), 0.0
    where = f"the tool ends at {xyz_text(end.xyz)}"
    if dist > check.tolerance_mm:
        return Outcome(
            False,
            f"{where}, {dist:.1f} mm from {xyz_text(check.pose)} "
            f"(tolerance {check.tolerance_mm:g} mm)",
            _last_move_line(run),
        )
    if angle > check.tolerance_deg:
        return Outcome(
            False,
            f"{where} but turned {angle:.1f}° from A, B, C = "
            f"{', '.join(f'{v:g}' for v in check.pose[3:])} "
            f"(tolerance {check.tolerance_deg:g}°)",
            _last_move_line(run),
        )
    return Outcome(True, f"{where} ({dist:.1f} mm off)")


def visits(check: Visits, run: Run) -> Outcome:
    """Each pose is passed within the tolerance: the path's samples and every move's end."""
    stops = [(m.end, m.target.xyz, m.line) for m in run.moves]
    samples = [(p.time, (p.x, p.y, p.z), p.line) for p in run.path]
    seen = sorted(stops + samples, key=lambda s: s[0])
    after = -math.inf
    for pose in check.poses:
        candidates = [s for s in seen if s[0] >= after]
        best = min(candidates, key=lambda s: math.dist(s[1], pose[:3]), default=None)
        if best is None or math.dist(best[1], pose[:3]) > check.tolerance_mm:
            near = (
                f"; the nearest it came is {math.dist(best[1], pose[:3]):.1f} mm away"
                if best is not None
                else ""
            )
            order = " after the poses before it" if check.in_order and after > -math.inf else ""
            return Outcome(
                False,
                f"the tool never passes {xyz_text(pose)}{order}{near}",
                best[2] if best is not None else None,
            )
        if check.in_order:
            after = min(s[0] for s in candidates if math.dist(s[1], pose[:3]) <= check.tolerance_mm)
    return Outcome(True, f"the tool passes all {len(check.poses)} poses")


def part_at(check: PartAt, run: Run) -> Outcome:
    """Where the part ended (the centre of its bottom face); the line that let it go there
    (its last HOPEN) or, when it is still held, the HCLOSE that took it."""
    part = next((p for p in run.parts if p.name == check.part), None)
    if part is None:
        return Outcome(False, f"the run knows no part {check.part!r}")
    moved = [a for a in run.hands if a.part == check.part]
    line = moved[-1].line if moved else None
    if part.held:
        return Outcome(False, f"{check.part} is still in the hand at the end", line)
    dist = math.dist(part.position, check.position)
    where = f"{check.part} ends at {xyz_text(part.position)}"
    if dist > check.tolerance_mm:
        if not moved:
            return Outcome(
                False,
                f"{check.part} never moved from {xyz_text(part.position)}; "
                f"its place is {xyz_text(check.position)}",
            )
        return Outcome(
            False,
            f"{where}, {dist:.1f} mm from its place {xyz_text(check.position)} "
            f"(at most {check.tolerance_mm:g} mm)",
            line,
        )
    return Outcome(True, f"{where} ({dist:.1f} mm off)")


def hand(check: Hand, run: Run) -> Outcome:
    """The hand's opens (or closes), in order, each where the tool was (TCP, mm)."""
    change = HandChange.OPEN if check.action is HandAction.OPEN else HandChange.CLOSE
    past = "opened" if check.action is HandAction.OPEN else "closed"
    if check.with_part:
        past = "let go of a part" if check.action is HandAction.OPEN else "took a part"
    events = [
        a
        for a in run.hands
        if a.hand == check.hand and a.change is change and (a.part or not check.with_part)
    ]
    for i, want in enumerate(check.at):
        if i >= len(events):
            return _missing(check, run, i, past, events)
        got = events[i]
        dist = math.dist(got.pose[:3], want)
        if dist > check.tolerance_mm:
            return Outcome(
                False,
                f"the hand {past} at {xyz_text(got.pose)}, {dist:.1f} mm from "
                f"{xyz_text(want)} (place {i + 1} of {len(check.at)}; "
                f"at most {check.tolerance_mm:g} mm)",
                got.line,
            )
    if len(events) > len(check.at):
        extra = events[len(check.at)]
        return Outcome(
            False,
            f"the hand {past} {len(events)} times, {len(check.at)} expected: once "
            f"more at {xyz_text(extra.pose)}",
            extra.line,
        )
    verb = "opens" if check.action is HandAction.OPEN else "closes"
    return Outcome(True, f"hand {check.hand} {verb} at all {len(check.at)} places")


def no_collision(run: Run) -> Outcome:
    errors = [f for f in run.findings if f.severity is Severity.ERROR]
    if not errors:
        return Outcome(True, "no collision and no pre-flight error")
    first = min(errors, key=lambda f: f.segment.start if f.segment is not None else -1.0)
    more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
    return Outcome(False, first.message + more, first.line)


def cycle_time(check: CycleTime, run: Run) -> Outcome:
    if run.cycle_time is None:
        return Outcome(
            False,
            f"the run does not reach END (stopped after {run.duration:.1f} s)",
            run.error.location.line if run.error is not None else None,
        )
    if run.cycle_time > check.max_s:
        late = next((m for m in run.moves if m.end > check.max_s), None)
        return Outcome(
            False,
            f"the cycle takes {run.cycle_time:.1f} s, more than {check.max_s:g} s"
            + (f"; the time runs out during line {late.line}" if late and late.line else ""),
            late.line if late is not None else None,
        )
    return Outcome(True, f"the cycle takes {run.cycle_time:.1f} s")


def io(check: Io, run: Run, program: A.Program) -> Outcome:
    """The outputs at the end; a wrong one points at the last line that sets it."""
    wrong = [
        (bit, value)
        for bit, value in sorted(check.outputs.items())
        if run.outputs.get(bit, 0) != value
    ]
    if not wrong:
        return Outcome(True, "the outputs are as expected")
    said = "; ".join(f"M_OUT({b}) is {run.outputs.get(b, 0)}, expected {v}" for b, v in wrong)
    setting = lines_setting_output(program, wrong[0][0])
    if not setting:
        return Outcome(False, f"at the end {said}; the program never sets M_OUT({wrong[0][0]})")
    return Outcome(False, f"at the end {said}", setting[-1])


def uses(check: Uses, program: A.Program) -> Outcome:
    missing = [normalise(s) for s in check.statements if not lines_using(program, s)]
    if missing:
        return Outcome(False, f"the program does not use {', '.join(missing)}")
    return Outcome(True, f"the program uses {', '.join(normalise(s) for s in check.statements)}")


def avoids(check: Avoids, program: A.Program) -> Outcome:
    found = [(lines_using(program, s), normalise(s)) for s in check.statements]
    used = [(lines[0], name) for lines, name in found if lines]
    if used:
        line, name = min(used)
        return Outcome(False, f"line {line} uses {name}, which this assignment rules out", line)
    return Outcome(True, f"the program uses none of {', '.join(n for _, n in found)}")


def _missing(check: Hand, run: Run, i: int, past: str, events: list[Action]) -> Outcome:
    """The i-th place has no event: a close that took nothing after the last one that did
    is the likely culprit (an open holding nothing is usual: a HOPEN at the start); else
    the move that arrived there without the hand acting."""
    want = check.at[i]
    change = HandChange.OPEN if check.action is HandAction.OPEN else HandChange.CLOSE
    after = events[-1].time if events else -math.inf
    empty = [
        a
        for a in run.hands
        if a.hand == check.hand and a.change is change and a.part is None and a.time > after
    ]
    place = f"place {i + 1} of {len(check.at)}"
    if check.with_part and change is HandChange.CLOSE and empty:
        a = empty[0]
        return Outcome(
            False,
            f"the hand closed at {xyz_text(a.pose)} and took nothing: "
            f"{math.dist(a.pose[:3], want):.1f} mm from {xyz_text(want)} ({place})",
            a.line,
        )
    arrived = [m for m in run.moves if math.dist(m.target.xyz, want) <= check.tolerance_mm]
    act = "open" if change is HandChange.OPEN else "close"
    if arrived:
        return Outcome(
            False,
            f"the tool reaches {xyz_text(want)} ({place}) at line {arrived[0].line}, "
            f"but the hand does not {act} there",
            arrived[0].line,
        )
    count = f"{len(events)} time{'s' if len(events) != 1 else ''}"
    return Outcome(False, f"the hand {past} {count}, never at {xyz_text(want)} ({place})")
