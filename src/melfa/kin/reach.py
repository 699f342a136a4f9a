"""Can the RV-6S take the points of a points file? (`melfa check` warnings on a `.POS` file.)

`unreachable_points(points)` is pure kinematics on `melfa.lang.points.PointDef`s:

* an XYZ point (POS) is solved with `melfa.kin.ik` under its own flags (FL1 and FL2). If that
  fails, every other arm configuration is tried, so the reason can say "reachable only with
  flags (6,0)" rather than just "unreachable"; if none works, the reason says how far the
  wrist centre is from the shoulder, or which joint limit the solution breaks;
* a joint point (JNT) is checked against the joint ranges and interference limits
  (`melfa.kin.check_limits`).

`reach_diagnostics(points, text)` turns the findings into `Diagnostic`s on the points file's
lines (the name underlined), for `melfa check` and the web API alike. It lives here and not in
`melfa.lang` because lang must not depend on kin (numpy, the robot model);
`melfa.lang.diagnostics` and `melfa.lang.points` are pure values with no dependencies, so
kin importing them keeps the layering one-way.

The findings are **warnings**, never errors: points are checked as flange positions in robot
coordinates (no TOOL, no BASE), and a program that sets TOOL or BASE reaches other flange
positions; the FL1 bit meanings are a [GUESS] (`melfa.kin.flags`).
"""

from __future__ import annotations

import enum
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from melfa.kin.errors import (
    InterferenceLimitExceeded,
    JointLimitExceeded,
    KinematicsError,
    LimitExceeded,
)
from melfa.kin.flags import ALL_CONFIGURATIONS
from melfa.kin.model import (
    BASE_HEIGHT,
    ELBOW_OFFSET,
    FLANGE,
    FOREARM,
    SHOULDER_OFFSET,
    UPPER_ARM,
    check_limits,
)
from melfa.kin.pose import Pose
from melfa.kin.solver import flange_target, ik, structure_flags
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.points import PointDef, PointKind

__all__ = ["ReachKind", "reach_diagnostics", "unreachable_points"]

ROBOT = "RV-6S"
MAX_STRETCH = UPPER_ARM + math.hypot(ELBOW_OFFSET, FOREARM)
"""Shoulder (J2 axis) to wrist centre, arm stretched, mm (≈610)."""
MIN_FOLD = abs(UPPER_ARM - math.hypot(ELBOW_OFFSET, FOREARM))
"""Shoulder to wrist centre, arm folded, mm (≈50)."""


class ReachKind(enum.Enum):
    """Why a point cannot be taken; the value is the diagnostic's rule name."""

    OUT_OF_REACH = "point-out-of-reach"
    NEEDS_FLAGS = "point-flags"
    JOINT_LIMIT = "point-joint-limit"
    INTERFERENCE = "point-interference"


@dataclass(frozen=True, slots=True)
class _Finding:
    point: PointDef
    kind: ReachKind
    reason: str  # reads after "Point Pname ": "is out of the RV-6S's reach (…)"
    suggestion: str | None = None


def unreachable_points(points: Iterable[PointDef]) -> list[tuple[str, str]]:
    """(name, reason) for each point the RV-6S cannot take, in the order given.

    The reason reads after the name: ``f"Point {name} {reason}"``. Points with an omitted
    element (``(400,,300,…)``) or a value that is not finite are skipped: there is nothing
    definite to solve.

    >>> from melfa.lang.points import PointDef
    >>> unreachable_points([PointDef.pos("Pok", (400, 0, 450, 180, 0, 180)),
    ...                     PointDef.jnt("Jbad", (0, 140, 90, 0, 90, 0))])
    [('Jbad', 'has J2 = 140°, beyond its limit -92…135°')]
    """
    return [(f.point.name, f.reason) for f in _findings(points)]


def reach_diagnostics(points: Iterable[PointDef], text: str) -> list[Diagnostic]:
    """Warnings for the points that cannot be reached, on their lines of `text`.

    `text` is the points file the points were read from (`PointDef.line` indexes it); the
    warning underlines the point's name, or the whole line if the name is not found there.
    """
    lines = text.split("\n")
    out: list[Diagnostic] = []
    for f in _findings(points):
        number = f.point.line if 1 <= f.point.line <= len(lines) else 1
        source = lines[number - 1].removesuffix("\r") if lines else ""
        found = re.search(rf"(?<![A-Za-z0-9_]){re.escape(f.point.name)}\s*=", source)
        start, end = (
            (found.start(), found.start() + len(f.point.name)) if found else (0, len(source))
        )
        out.append(
            Diagnostic(
                number,
                start + 1,
                number,
                end + 1,
                Severity.WARNING,
                f"Point {f.point.name} {f.reason}",
                f.kind.value,
                suggestion=f.suggestion,
            )
        )
    return out


# --- assessing one point ----------------------------------------------------------------


def _findings(points: Iterable[PointDef]) -> list[_Finding]:
    out = []
    with np.errstate(all="ignore"):  # odd inputs give NaNs, which the solver reports
        for point in points:
            values = point.values[:6]
            if any(v is None or not math.isfinite(v) for v in values):
                continue
            numbers = [float(v) for v in values if v is not None]
            found = _assess_joints(point, numbers) if point.kind is PointKind.JNT else None
            if point.kind is PointKind.POS:
                found = _assess_pose(point, numbers)
            if found is not None:
                out.append(found)
    return out


def _degrees(value: float) -> str:
    return f"{value:.4g}°" if abs(value) < 1000 else f"{value:.0f}°"


def _limit_finding(point: PointDef, err: LimitExceeded, verb: str) -> _Finding:
    if isinstance(err, JointLimitExceeded):
        lo, hi = err.limits
        limit = f"{lo:g}…{hi:g}°"
        return _Finding(
            point,
            ReachKind.JOINT_LIMIT,
            f"{verb} J{err.joint} = {_degrees(err.value)}, beyond its limit {limit}",
            f"Bring J{err.joint} within {limit}, or teach the point again on the robot."
            if point.kind is PointKind.JNT
            else "Move the point, or teach it again on the robot.",
        )
    assert isinstance(err, InterferenceLimitExceeded)
    return _Finding(
        point,
        ReachKind.INTERFERENCE,
        f"would make the arm hit itself ({err.rule})",
        "Teach the point again in a pose where the arm is clear of itself.",
    )


def _assess_joints(point: PointDef, joints: Sequence[float]) -> _Finding | None:
    try:
        check_limits(joints)
    except LimitExceeded as err:
        return _limit_finding(point, err, "has")
    return None


def _flags_text(fl1: int, fl2: int) -> str:
    return f"({fl1},{0 if fl2 == 0 else f'&H{fl2:08X}'})"


def _assess_pose(point: PointDef, values: Sequence[float]) -> _Finding | None:
    assert point.fl1 is not None and point.fl2 is not None  # a POS PointDef has flags
    x, y, z, a, b, c = values
    pose = Pose(x, y, z, a, b, c, point.fl1, point.fl2)
    try:
        ik(pose)
        return None
    except KinematicsError as err:
        own_error = err
    working: list[str] = []
    for config in ALL_CONFIGURATIONS:
        try:
            joints = ik(Pose(x, y, z, a, b, c, config.fl1, 0), use_fl2=False)
        except KinematicsError:
            continue
        flags = _flags_text(*structure_flags(joints))
        if flags not in working:
            working.append(flags)
    given = _flags_text(point.fl1, point.fl2)
    if working:
        shown = " or ".join(working[:3])
        return _Finding(
            point,
            ReachKind.NEEDS_FLAGS,
            f"is reachable only with flags {shown}, not {given}",
            f"Change the flags to {working[0]}, or teach the point again in the pose you want.",
        )
    if isinstance(own_error, LimitExceeded):
        return _limit_finding(point, own_error, "needs")
    return _Finding(
        point,
        ReachKind.OUT_OF_REACH,
        f"is out of the {ROBOT}'s reach ({_distance_text(pose)})",
        "Move the point closer to the robot, or teach it again on the robot.",
    )


def _distance_text(pose: Pose) -> str:
    """How far the wrist centre is from the shoulder, against what the arm spans."""
    t = flange_target(pose)
    wrist = t[:3, 3] - FLANGE * t[:3, 2]
    radial = math.hypot(float(wrist[0]), float(wrist[1])) - SHOULDER_OFFSET
    distance = math.hypot(radial, float(wrist[2]) - BASE_HEIGHT)
    if distance < MIN_FOLD:
        return (
            f"its wrist centre is {distance:.0f} mm from the shoulder; "
            f"the arm folds to {MIN_FOLD:.0f} mm at the closest"
        )
    return (
        f"its wrist centre is {distance:.0f} mm from the shoulder; "
        f"the arm stretches to {MAX_STRETCH:.0f} mm"
    )
