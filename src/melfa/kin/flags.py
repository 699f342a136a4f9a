"""Structure flags FL1 (arm configuration) and FL2 (multi-rotation), rv6s.md §6.

FL1 bit order [GUESS, deduced from "7 = RAN" (DOC S1 RDFL1/SETFL1) and the common Mitsubishi
convention; verify on a T/B]: see `FL1_RIGHT`, `FL1_ABOVE`, `FL1_NONFLIP`.

FL2 is 32 bits, 4 signed bits per axis, J1 in the lowest nibble [DOC S5 RDFL2]; per axis 0 means
-180..+180°, +1 means 180..540°, -1 means -540..-180°. On the RV-6S only J6 can turn past ±180°.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

FL1_RIGHT = 4
"""[GUESS] bit set = Right: the wrist centre is in front of the J1 axis (on the arm's side)."""
FL1_ABOVE = 2
"""[GUESS] bit set = Above: the wrist centre is above the J2–J3 line (elbow up)."""
FL1_NONFLIP = 1
"""[GUESS; CODE S12 ties it to the sign of J5] bit set = Non-flip: J5 >= 0."""

FL2_NIBBLE_BITS = 4
FL2_MASK = 0xFFFFFFFF


@dataclass(frozen=True, slots=True)
class Configuration:
    """The three FL1 choices as booleans."""

    right: bool = True
    above: bool = True
    nonflip: bool = True

    @classmethod
    def from_fl1(cls, fl1: int) -> Configuration:
        return cls(bool(fl1 & FL1_RIGHT), bool(fl1 & FL1_ABOVE), bool(fl1 & FL1_NONFLIP))

    @property
    def fl1(self) -> int:
        return (
            (FL1_RIGHT if self.right else 0)
            | (FL1_ABOVE if self.above else 0)
            | (FL1_NONFLIP if self.nonflip else 0)
        )

    @property
    def letters(self) -> str:
        """The RDFL1 letters, e.g. "RAN" for 7.

        >>> Configuration.from_fl1(6).letters
        'RAF'
        """
        return (
            ("R" if self.right else "L")
            + ("A" if self.above else "B")
            + ("N" if self.nonflip else "F")
        )


ALL_CONFIGURATIONS: tuple[Configuration, ...] = tuple(
    Configuration.from_fl1(v) for v in (7, 6, 5, 4, 3, 2, 1, 0)
)


def turns_for_angle(angle: float) -> int:
    """The FL2 rotation count of one joint angle (degrees).

    >>> [turns_for_angle(a) for a in (180.0, 181.0, -180.0, -181.0)]
    [0, 1, 0, -1]
    """
    if angle > 180.0:
        return math.ceil((angle - 180.0) / 360.0)
    if angle < -180.0:
        return math.floor((angle + 180.0) / 360.0)
    return 0


def fl2_get(fl2: int, axis: int) -> int:
    """Signed rotation count (-8..7) of `axis` (1-based), like RDFL2.

    >>> fl2_get(15728640, 6), fl2_get(0x00100000, 6)
    (-1, 1)
    """
    nib = ((fl2 & FL2_MASK) >> (FL2_NIBBLE_BITS * (axis - 1))) & 0xF
    return nib - 16 if nib >= 8 else nib


def fl2_set(fl2: int, axis: int, turns: int) -> int:
    """FL2 with `axis` (1-based) set to `turns` (-8..7), like SETFL2.

    >>> hex(fl2_set(0, 6, -1))
    '0xf00000'
    """
    if not -8 <= turns <= 7:
        raise ValueError(f"FL2 rotation count {turns} is outside -8..7")
    shift = FL2_NIBBLE_BITS * (axis - 1)
    cleared = (fl2 & FL2_MASK) & ~(0xF << shift)
    return (cleared | ((turns & 0xF) << shift)) & FL2_MASK


def fl2_from_joints(joints: Sequence[float]) -> int:
    """FL2 for a joint vector: each axis' rotation count in its nibble."""
    fl2 = 0
    for i, q in enumerate(joints):
        t = turns_for_angle(float(q))
        if t:
            fl2 = fl2_set(fl2, i + 1, t)
    return fl2
