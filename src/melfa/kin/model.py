"""The RV-6S model: DH table, joint ranges, joint speeds, interference limits (rv6s.md §2–4).

Angles in degrees, lengths in mm. `check_limits` is what the simulator applies before and
during every move.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from melfa.kin.errors import InterferenceLimitExceeded, JointLimitExceeded
from melfa.kin.pose import Joints


@dataclass(frozen=True, slots=True)
class DHRow:
    """One standard-DH row: T = Rz(θ)·Tz(d)·Tx(a)·Rx(α), θ = q + offset [CODE S9]."""

    a: float
    d: float
    alpha: float
    offset: float


DH: tuple[DHRow, ...] = (
    DHRow(85.0, 350.0, -90.0, 0.0),
    DHRow(280.0, 0.0, 0.0, -90.0),
    DHRow(100.0, 0.0, -90.0, -90.0),
    DHRow(0.0, 315.0, 90.0, 0.0),
    DHRow(0.0, 0.0, -90.0, 0.0),
    DHRow(0.0, 85.0, 0.0, 180.0),
)
"""rv6s.md §4 [CODE S9, S14]; d1 = 350 puts the base frame at the mounting surface [DERIVED]."""

SHOULDER_OFFSET = DH[0].a  # 85 mm, J1 axis to J2 axis
BASE_HEIGHT = DH[0].d  # 350 mm, mounting surface to J2
UPPER_ARM = DH[1].a  # 280 mm
ELBOW_OFFSET = DH[2].a  # 100 mm
FOREARM = DH[3].d  # 315 mm
FLANGE = DH[5].d  # 85 mm, wrist centre (P-point) to flange

HOME = Joints(0.0, 0.0, 90.0, 0.0, 90.0, 0.0)
"""Hand-down home used by S9; FK gives (400, 0, 645, 180, 0, 180)."""

JOINT_LIMITS: tuple[tuple[float, float], ...] = (
    (-170.0, 170.0),
    (-92.0, 135.0),
    (-107.0, 166.0),
    (-160.0, 160.0),
    (-120.0, 120.0),
    (-360.0, 360.0),
)
"""Joint ranges in degrees [DOC S3 Table 2-1; same in CODE S9]."""

JOINT_MAX_SPEED: tuple[float, ...] = (401.0, 321.0, 401.0, 352.0, 450.0, 660.0)
"""Maximum joint speeds in deg/s [DOC S3]."""

MAX_RESULTANT_SPEED = 9300.0
"""Maximum resultant TCP speed, mm/s [DOC S3 Table 2-1]."""

LIMIT_EPSILON = 1e-6
"""Tolerance (degrees) so a joint exactly on a limit, after float round-off, still passes."""


class Interference(enum.Enum):
    """Which interference rows (rv6s.md §3) `check_limits` enforces."""

    NONE = "none"
    TRUSTED = "trusted"
    """The four legible rows of the manual's notes (the default)."""
    ALL = "all"
    """Also the two rows from the garbled passage [GUESS until checked on the robot]."""


@dataclass(frozen=True, slots=True)
class InterferenceRule:
    """`applies(q)` selects the region; `ok(q)` is the constraint that must hold there."""

    text: str
    applies: Callable[[Sequence[float]], bool]
    ok: Callable[[Sequence[float]], bool]
    trusted: bool


INTERFERENCE_RULES: tuple[InterferenceRule, ...] = (
    InterferenceRule(
        "-45 <= J2 < 15 requires J2 + 2*J3 >= -200",
        lambda q: -45.0 <= q[1] < 15.0,
        lambda q: q[1] + 2.0 * q[2] >= -200.0 - LIMIT_EPSILON,
        True,
    ),
    InterferenceRule(
        "|J1| <= 75 and J2 < -45 requires J2 + J3 >= 8",
        lambda q: abs(q[0]) <= 75.0 and q[1] < -45.0,
        lambda q: q[1] + q[2] >= 8.0 - LIMIT_EPSILON,
        True,
    ),
    InterferenceRule(
        "|J1| > 75 and J2 < -45 requires J2 + J3 >= -40",
        lambda q: abs(q[0]) > 75.0 and q[1] < -45.0,
        lambda q: q[1] + q[2] >= -40.0 - LIMIT_EPSILON,
        True,
    ),
    InterferenceRule(
        "-105 <= J1 <= 95 and J2 >= 123 requires J3 >= -40",
        lambda q: -105.0 <= q[0] <= 95.0 and q[1] >= 123.0,
        lambda q: q[2] >= -40.0 - LIMIT_EPSILON,
        True,
    ),
    InterferenceRule(  # [DOC S3, garbled passage] confirm before trusting
        "J1 < -105 or J1 > 95 requires J2 >= 110",
        lambda q: q[0] < -105.0 or q[0] > 95.0,
        lambda q: q[1] >= 110.0 - LIMIT_EPSILON,
        False,
    ),
    InterferenceRule(  # [DOC S3, garbled passage] confirm before trusting
        "85 <= J2 <= 110 requires J2 - J3 <= 150",
        lambda q: 85.0 <= q[1] <= 110.0,
        lambda q: q[1] - q[2] <= 150.0 + LIMIT_EPSILON,
        False,
    ),
)

DEFAULT_INTERFERENCE = Interference.TRUSTED


def check_limits(
    joints: Sequence[float], interference: Interference = DEFAULT_INTERFERENCE
) -> None:
    """Raise `JointLimitExceeded` (first joint out of range) or `InterferenceLimitExceeded`.

    >>> check_limits(HOME)
    >>> check_limits((0, 0, 90, 0, 130, 0))
    Traceback (most recent call last):
    ...
    melfa.kin.errors.JointLimitExceeded: J5 = 130.00 deg is outside its range -120 .. 120 deg
    """
    for i, (q, (lo, hi)) in enumerate(zip(joints, JOINT_LIMITS, strict=True)):
        if not lo - LIMIT_EPSILON <= q <= hi + LIMIT_EPSILON:
            raise JointLimitExceeded(i + 1, float(q), (lo, hi))
    violated = interference_violation(joints, interference)
    if violated is not None:
        raise InterferenceLimitExceeded(violated.text, tuple(float(q) for q in joints))


def interference_violation(
    joints: Sequence[float], interference: Interference = DEFAULT_INTERFERENCE
) -> InterferenceRule | None:
    """The first interference rule the joints break, or None."""
    if interference is Interference.NONE:
        return None
    for rule in INTERFERENCE_RULES:
        if not rule.trusted and interference is not Interference.ALL:
            continue
        if rule.applies(joints) and not rule.ok(joints):
            return rule
    return None


def within_limits(
    joints: Sequence[float], interference: Interference = DEFAULT_INTERFERENCE
) -> bool:
    """True when `check_limits` would pass."""
    for q, (lo, hi) in zip(joints, JOINT_LIMITS, strict=True):
        if not lo - LIMIT_EPSILON <= q <= hi + LIMIT_EPSILON:
            return False
    return interference_violation(joints, interference) is None
