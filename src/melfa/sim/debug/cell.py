"""The robot's cell: the table, fixtures, the parts a program moves, the gripper that moves
them, and simple devices (part-present sensors, conveyors). Pure records with a JSON form.

Coordinates are the world frame in mm (the robot's base frame unless the program sets BASE:
X forward, Z up, 0 at the mounting surface), the frame positions are written in. A solid
(a fixture or a part) is a box or an upright cylinder placed by the centre of its bottom face
(`position`) and turned by `rz` degrees about the vertical; a part standing on the table at
z = 0 has ``position[2] == 0``. Instructors edit the cell as JSON (docs/simulator.md)::

    {"floor_z": 0,
     "gripper": {"hand": 1, "grip": 107.5, "tolerance": 10, "length": 60, "radius": 30},
     "fixtures": [{"name": "bench", "shape": "box", "size": [350, 800, 100],
                   "position": [425, -50, 0]}],
     "parts": [{"name": "block 1", "shape": "cylinder", "diameter": 54, "height": 25,
                "position": [350, -250, 100]}],
     "sensors": [{"name": "at pick", "input": 8, "min": [..], "max": [..]}],
     "conveyors": [{"name": "belt", "output": 10, "size": [..], "position": [..],
                    "velocity": [100, 0]}]}

`boxes` (axis-aligned obstacles by `min`/`max`, the first cells' form) are still read:
the tool point must stay out of them, and the arm too. `floor_z` null means "no table
check". `Cell.from_json` says what is wrong and where, in plain words (`CellError`);
`to_json` writes the same form back. The run in a cell is `cell_world.CellWorld`.
"""

from __future__ import annotations

import enum
import hashlib
import json
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, TypeVar

from melfa.protocol.limits import HANDS, span_text

DEFAULT_FLOOR_Z = 0.0
"""The table the arm stands on: its mounting surface (z = 0 of the base frame)."""

MAX_BOXES = 100
MAX_SOLIDS = 200
"""At most this many fixtures, parts, sensors or conveyors each (a lab cell has a dozen)."""

T = TypeVar("T")


class CellError(ValueError):
    """A cell description that cannot be used, with what and where."""


Vec = tuple[float, float, float]


class Shape(enum.Enum):
    BOX = "box"
    CYLINDER = "cylinder"  # upright: its axis is vertical


@dataclass(frozen=True, slots=True)
class Box:
    """An axis-aligned box obstacle (mm, base frame); `min` ≤ `max` on each axis."""

    name: str
    min: Vec
    max: Vec

    def contains(self, x: float, y: float, z: float) -> bool:
        lo, hi = self.min, self.max
        return lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1] and lo[2] <= z <= hi[2]

    def solid(self) -> Solid:
        """The same box as a fixture (what the arm's collision check reads)."""
        lo, hi = self.min, self.max
        centre = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, lo[2])
        size = (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])
        return Solid(self.name, Shape.BOX, size, centre)

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "min": list(self.min), "max": list(self.max)}


@dataclass(frozen=True, slots=True)
class Solid:
    """A fixture or a part: a box (`size` x, y, z) or an upright cylinder (`size` is
    diameter, diameter, height), its bottom face centred on `position`, turned `rz`°."""

    name: str
    shape: Shape
    size: Vec
    position: Vec
    rz: float = 0.0

    @property
    def height(self) -> float:
        return self.size[2]

    @property
    def top(self) -> float:
        return self.position[2] + self.size[2]

    @property
    def centre(self) -> Vec:
        """The middle of the solid (where a gripper holds a part)."""
        x, y, z = self.position
        return (x, y, z + self.size[2] / 2)

    def moved(self, position: Vec, rz: float | None = None) -> Solid:
        return Solid(self.name, self.shape, self.size, position, self.rz if rz is None else rz)

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name, "shape": self.shape.value}
        if self.shape is Shape.CYLINDER:
            out |= {"diameter": self.size[0], "height": self.size[2]}
        else:
            out["size"] = list(self.size)
        out["position"] = list(self.position)
        if self.rz:
            out["rz"] = self.rz
        return out


@dataclass(frozen=True, slots=True)
class Gripper:
    """The physical hand on the flange (it does not follow the program's TOOL).

    `hand` is the HOPEN/HCLOSE number that works it. A part whose centre is within
    `tolerance` mm of the grip point (`grip` mm from the flange along its Z axis) when the
    hand closes is carried. Its body, for collisions, is a capsule of `radius` from the
    flange to `length` mm along the flange's Z (the fingers are not checked)."""

    hand: int = 1
    grip: float = 0.0
    tolerance: float = 10.0
    length: float = 0.0
    radius: float = 30.0

    def to_json(self) -> dict[str, Any]:
        return {
            "hand": self.hand,
            "grip": self.grip,
            "tolerance": self.tolerance,
            "length": self.length,
            "radius": self.radius,
        }


@dataclass(frozen=True, slots=True)
class Sensor:
    """A part-present sensor: input ``M_IN(input)`` is 1 while a part's centre is inside
    the axis-aligned region `min`..`max` (mm)."""

    name: str
    input: int
    min: Vec
    max: Vec

    def sees(self, point: Vec) -> bool:
        return all(lo <= p <= hi for p, lo, hi in zip(point, self.min, self.max, strict=True))

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "input": self.input,
            "min": list(self.min),
            "max": list(self.max),
        }


@dataclass(frozen=True, slots=True)
class Conveyor:
    """A belt: a box (`size`, bottom centred on `position`, axis-aligned) whose top carries
    the parts standing on it at `velocity` (mm/s along X and Y) while output
    ``M_OUT(output)`` is 1; a part stops where its centre reaches the belt's end."""

    name: str
    output: int
    size: Vec
    position: Vec
    velocity: tuple[float, float]

    def solid(self) -> Solid:
        return Solid(self.name, Shape.BOX, self.size, self.position)

    def to_json(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "output": self.output,
            "size": list(self.size),
            "position": list(self.position),
            "velocity": list(self.velocity),
        }


@dataclass(frozen=True, slots=True)
class Cell:
    """The table plane (None: not checked), obstacles, fixtures, parts, gripper, devices."""

    floor_z: float | None = DEFAULT_FLOOR_Z
    boxes: tuple[Box, ...] = field(default_factory=tuple)
    fixtures: tuple[Solid, ...] = field(default_factory=tuple)
    parts: tuple[Solid, ...] = field(default_factory=tuple)
    gripper: Gripper = field(default_factory=Gripper)
    sensors: tuple[Sensor, ...] = field(default_factory=tuple)
    conveyors: tuple[Conveyor, ...] = field(default_factory=tuple)

    @property
    def obstacles(self) -> tuple[Solid, ...]:
        """Every solid that never moves: the fixtures, the boxes and the conveyors' belts."""
        return (
            self.fixtures
            + tuple(b.solid() for b in self.boxes)
            + tuple(c.solid() for c in self.conveyors)
        )

    def part(self, name: str) -> Solid:
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(name)

    def to_json(self) -> dict[str, Any]:
        return {
            "floor_z": self.floor_z,
            "boxes": [b.to_json() for b in self.boxes],
            "fixtures": [f.to_json() for f in self.fixtures],
            "parts": [p.to_json() for p in self.parts],
            "gripper": self.gripper.to_json(),
            "sensors": [s.to_json() for s in self.sensors],
            "conveyors": [c.to_json() for c in self.conveyors],
        }

    def digest(self) -> str:
        """A hash of the cell as `to_json` writes it: the version of the cell a pre-flight
        ran in (the instructor's gate counts a pass only in the cell as it is now).

        >>> Cell().digest() == Cell.from_json('{"floor_z": 0}').digest() != Cell(None).digest()
        True
        """
        text = json.dumps(self.to_json(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

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
            raise CellError("a cell is a JSON object with floor_z, fixtures, parts …")
        unknown = sorted(set(data) - set(_FIELDS))
        if unknown:
            raise CellError(
                f"unknown field(s) {', '.join(unknown)} (a cell has {', '.join(_FIELDS)})"
            )
        floor = data.get("floor_z", DEFAULT_FLOOR_Z)
        if floor is not None:
            floor = _number(floor, "floor_z")
        boxes = _list(data, "boxes", "box", _box, MAX_BOXES)
        fixtures = _list(data, "fixtures", "fixture", _solid, MAX_SOLIDS)
        parts = _list(data, "parts", "part", _solid, MAX_SOLIDS)
        sensors = _list(data, "sensors", "sensor", _sensor, MAX_SOLIDS)
        conveyors = _list(data, "conveyors", "conveyor", _conveyor, MAX_SOLIDS)
        for kind, items in (("part", parts), ("fixture", fixtures)):
            _unique([s.name for s in items], kind)
        gripper = _gripper(data.get("gripper", {}))
        return cls(floor, boxes, fixtures, parts, gripper, sensors, conveyors)


_FIELDS = ("floor_z", "boxes", "fixtures", "parts", "gripper", "sensors", "conveyors")


def _unique(names: list[str], kind: str) -> None:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise CellError(f"two {kind}s are named {name!r}: give each its own name")
        seen.add(name)


def _list(
    data: dict[str, Any], key: str, kind: str, read: Callable[[Any, str], T], limit: int
) -> tuple[T, ...]:
    items = data.get(key, [])
    if not isinstance(items, list):
        raise CellError(f"{key} must be a list")
    if len(items) > limit:
        raise CellError(f"at most {limit} {key}, got {len(items)}")
    out = []
    for i, item in enumerate(items, start=1):
        if not isinstance(item, dict):
            raise CellError(f"{kind} {i} must be an object")
        out.append(read(item, f"{kind} {i}"))
    return tuple(out)


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise CellError(f"{where} must be a number (mm), got {json.dumps(value)}")
    return float(value)


def _positive(value: Any, where: str) -> float:
    v = _number(value, where)
    if v <= 0:
        raise CellError(f"{where} must be more than 0 mm, got {v:g}")
    return v


def _bit(value: Any, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise CellError(f"{where} must be a signal number (0, 1, 2 …), got {json.dumps(value)}")
    return value


def _vec(value: Any, where: str) -> Vec:
    if not isinstance(value, list) or len(value) != 3:
        raise CellError(f"{where} must be [x, y, z] in mm")
    x, y, z = (_number(v, where) for v in value)
    return (x, y, z)


def _name(data: dict[str, Any], where: str, allowed: set[str]) -> str:
    unknown = sorted(set(data) - allowed - {"name"})
    name = data.get("name", where)
    if not isinstance(name, str) or not name.strip():
        raise CellError(f"{where}: name must be a non-empty text")
    if unknown:
        fields = ", ".join(sorted(allowed | {"name"}))
        raise CellError(f"{name.strip()!r}: unknown field(s) {', '.join(unknown)} ({fields})")
    return name.strip()


def _box(data: dict[str, Any], where: str) -> Box:
    name = _name(data, where, {"min", "max"})
    where = f"box {name!r}"
    lo = _vec(data.get("min"), f"{where}: min")
    hi = _vec(data.get("max"), f"{where}: max")
    if any(a > b for a, b in zip(lo, hi, strict=True)):
        raise CellError(f"{where}: min must not be above max on any axis")
    return Box(name, lo, hi)


def _solid(data: dict[str, Any], where: str) -> Solid:
    name = _name(data, where, {"shape", "size", "diameter", "height", "position", "rz"})
    where = f"{where.split()[0]} {name!r}"
    shape_text = data.get("shape", "box")
    try:
        shape = Shape(shape_text)
    except ValueError:
        raise CellError(f"{where}: shape must be box or cylinder, got {shape_text!r}") from None
    if shape is Shape.CYLINDER:
        d = _positive(data.get("diameter"), f"{where}: diameter")
        size = (d, d, _positive(data.get("height"), f"{where}: height"))
    else:
        sx, sy, sz = _vec(data.get("size"), f"{where}: size")
        size = (
            _positive(sx, f"{where}: size x"),
            _positive(sy, f"{where}: size y"),
            _positive(sz, f"{where}: size z"),
        )
    position = _vec(data.get("position"), f"{where}: position")
    rz = _number(data.get("rz", 0.0), f"{where}: rz (degrees)")
    return Solid(name, shape, size, position, rz)


def _sensor(data: dict[str, Any], where: str) -> Sensor:
    name = _name(data, where, {"input", "min", "max"})
    where = f"sensor {name!r}"
    lo = _vec(data.get("min"), f"{where}: min")
    hi = _vec(data.get("max"), f"{where}: max")
    if any(a > b for a, b in zip(lo, hi, strict=True)):
        raise CellError(f"{where}: min must not be above max on any axis")
    return Sensor(name, _bit(data.get("input"), f"{where}: input"), lo, hi)


def _conveyor(data: dict[str, Any], where: str) -> Conveyor:
    name = _name(data, where, {"output", "size", "position", "velocity"})
    where = f"conveyor {name!r}"
    sx, sy, sz = _vec(data.get("size"), f"{where}: size")
    size = (
        _positive(sx, f"{where}: size x"),
        _positive(sy, f"{where}: size y"),
        _positive(sz, f"{where}: size z"),
    )
    velocity = data.get("velocity")
    if not isinstance(velocity, list) or len(velocity) != 2:
        raise CellError(f"{where}: velocity must be [vx, vy] in mm/s")
    vx, vy = (_number(v, f"{where}: velocity") for v in velocity)
    position = _vec(data.get("position"), f"{where}: position")
    return Conveyor(name, _bit(data.get("output"), f"{where}: output"), size, position, (vx, vy))


def _gripper(data: Any) -> Gripper:
    if not isinstance(data, dict):
        raise CellError("gripper must be an object with hand, grip, tolerance, length, radius")
    allowed = {"hand", "grip", "tolerance", "length", "radius"}
    unknown = sorted(set(data) - allowed)
    if unknown:
        raise CellError(f"gripper: unknown field(s) {', '.join(unknown)}")
    d = Gripper()
    hand = data.get("hand", d.hand)
    if isinstance(hand, bool) or not isinstance(hand, int) or hand not in HANDS:
        raise CellError(
            f"gripper: hand must be a hand number {span_text(HANDS)}, got {json.dumps(hand)}"
        )
    grip = _number(data.get("grip", d.grip), "gripper: grip")
    length = _number(data.get("length", d.length), "gripper: length")
    tolerance = _positive(data.get("tolerance", d.tolerance), "gripper: tolerance")
    radius = _positive(data.get("radius", d.radius), "gripper: radius")
    if length < 0:
        raise CellError("gripper: length must not be negative")
    return Gripper(hand, grip, tolerance, length, radius)
