"""The MELFA BASIC statements the service sends for a student's *Move to*: built here, by
one typed function, never by string pasting at the call.

>>> move_statements("P1")
['MOV P1']
>>> move_statements((0, 0, 90, 0, 90, 0), joints=True)
['JMSVC=(0.000,0.000,90.000,0.000,90.000,0.000)', 'MOV JMSVC']
>>> move_statements("1P")
Traceback (most recent call last):
...
melfa.service.errors.InvalidArgument: '1P' is not a point name (letter, then ≤ 7 letters/digits)
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from melfa.service.errors import InvalidArgument

POINT_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,7}")
MOVE_POSE_VARIABLE = "PMSVC"
MOVE_JOINT_VARIABLE = "JMSVC"
"""Variables `move_statements` assigns for an explicit target (≤ 8 characters, L4300)."""


def move_statements(
    target: str | Sequence[float],
    *,
    linear: bool = False,
    joints: bool = False,
    flags: tuple[int, int] = (7, 0),
) -> list[str]:
    """``MOV P1`` for a point name; for six values (joint angles with ``joints``, else X, Y,
    Z, A, B, C with ``flags``) an assignment and the move. ``linear``: MVS."""
    verb = "MVS" if linear else "MOV"
    if isinstance(target, str):
        name = target.strip()
        if not POINT_NAME.fullmatch(name):
            raise InvalidArgument(
                f"{target!r} is not a point name (letter, then ≤ 7 letters/digits)", "target"
            )
        return [f"{verb} {name}"]
    try:
        values = [float(v) for v in target]
    except (TypeError, ValueError):
        raise InvalidArgument("a target is a point name or six numbers", "target") from None
    if len(values) != 6:
        raise InvalidArgument(f"a target needs 6 values, got {len(values)}", "target")
    text = ",".join(f"{v:.3f}" for v in values)
    if joints:
        return [f"{MOVE_JOINT_VARIABLE}=({text})", f"{verb} {MOVE_JOINT_VARIABLE}"]
    return [f"{MOVE_POSE_VARIABLE}=({text})({flags[0]},{flags[1]})", f"{verb} {MOVE_POSE_VARIABLE}"]


__all__ = ["MOVE_JOINT_VARIABLE", "MOVE_POSE_VARIABLE", "POINT_NAME", "move_statements"]
