"""The robot's cell, as simple as a pre-flight check needs: a table plane and boxes.

Coordinates are the robot's base frame in mm (X forward, Z up, 0 at the mounting surface),
the frame positions are written in. The tool (the TCP, under the program's TOOL) must stay
above `floor_z` and out of every `Box`. Instructors edit it as JSON::

    {"floor_z": 0.0,
     "boxes": [{"name": "feeder", "min": [250, -350, 0], "max": [450, -150, 120]}]}

`floor_z` null means "no table check". `Cell.from_json` says what is wrong and where, in
plain words (`CellError`); `to_json` writes the same form back.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

DEFAULT_FLOOR_Z = 0.0
"""The table the arm stands on: its mounting surface (z = 0 of the base frame)."""

MAX_BOXES = 100


class CellError(ValueError):
    """A cell description that cannot be used, with what and where."""


Vec = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned box obstacle (mm, base frame); `min` ≤ `max` on each axis."""

    name: str
    min: Vec
    max: Vec

    def contains(self, x: float, y: float, z: float) -> bool:
        lo, hi = self.min, self.max
        return lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1] and lo[2] <= z <= hi[2]

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "min": list(self.min), "max": list(self.max)}


@dataclass(frozen=True, slots=True)
class Cell:
    """The table plane (None: not checked) and the box obstacles."""

    floor_z: float | None = DEFAULT_FLOOR_Z
    boxes: tuple[Box, ...] = field(default_factory=tuple)

    def to_json(self) -> dict[str, Any]:
        return {"floor_z": self.floor_z, "boxes": [b.to_json() for b in self.boxes]}

    @classmethod
    def from_json(cls, data: str | dict[str, Any]) -> Cell:
        """A cell from its JSON text or the parsed object; `CellError` when it is wrong.

        >>> Cell.from_json('{"floor_z": -5, "boxes": [{"name": "jig", "min": [0,0,0],'
        ...                ' "max": [10,10,10]}]}').boxes[0].contains(5, 5, 5)
        True
        """
        if isinstance(data, str):
            try:
                data = json.loads(data)
            except json.JSONDecodeError as exc:
                raise CellError(f"not JSON: {exc.msg} at line {exc.lineno}") from None
        if not isinstance(data, dict):
            raise CellError("a cell is a JSON object with floor_z and boxes")
        unknown = sorted(set(data) - {"floor_z", "boxes"})
        if unknown:
            raise CellError(f"unknown field(s) {', '.join(unknown)} (a cell has floor_z, boxes)")
        floor = data.get("floor_z", DEFAULT_FLOOR_Z)
        if floor is not None:
            floor = _number(floor, "floor_z")
        boxes_data = data.get("boxes", [])
        if not isinstance(boxes_data, list):
            raise CellError("boxes must be a list")
        if len(boxes_data) > MAX_BOXES:
            raise CellError(f"at most {MAX_BOXES} boxes, got {len(boxes_data)}")
        boxes = tuple(_box(b, i) for i, b in enumerate(boxes_data, start=1))
        return cls(floor, boxes)


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CellError(f"{where} must be a number (mm), got {json.dumps(value)}")
    return float(value)


def _vec(value: Any, where: str) -> Vec:
    if not isinstance(value, list) or len(value) != 3:
        raise CellError(f"{where} must be [x, y, z] in mm")
    x, y, z = (_number(v, where) for v in value)
    return (x, y, z)


def _box(data: Any, index: int) -> Box:
    where = f"box {index}"
    if not isinstance(data, dict):
        raise CellError(f"{where} must be an object with name, min and max")
    name = data.get("name", f"box {index}")
    if not isinstance(name, str) or not name.strip():
        raise CellError(f"{where}: name must be a non-empty text")
    where = f"box {name!r}"
    lo = _vec(data.get("min"), f"{where}: min")
    hi = _vec(data.get("max"), f"{where}: max")
    if any(a > b for a, b in zip(lo, hi, strict=True)):
        raise CellError(f"{where}: min must not be above max on any axis")
    return Box(name.strip(), lo, hi)
