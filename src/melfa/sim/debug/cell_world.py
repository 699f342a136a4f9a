"""The cell during a run: where each part is, what the gripper holds, what the sensors see.

`CellWorld` is pure: the run tells it the time, the flange's transform and the outputs, and
it answers with parts and inputs (`cell_run` wires it to a simulated arm and its I/O).

* When the gripper's hand closes, the nearest loose part whose centre is within the
  gripper's `tolerance` of the grip point is carried: it keeps its place relative to the
  flange until the hand opens.
* When the hand opens, the part turns upright (keeping its heading) and drops straight
  down onto the highest thing under its footprint: the table, a fixture, a conveyor or
  another part (stacking works) and stays there; let go pushed into something, it rests
  on top of it. A part that stood on the one taken away
  drops too.
* A conveyor moves the parts standing on its belt while its output is on; a part stops
  where its centre reaches the belt's end. A sensor's input is 1 while a part's centre is
  in its region.

Every close and open is a `HandAction` (time, line, pose, part), and `snapshots` keep the
loose parts after each change, for the collision check of the moves that follow.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np

from melfa.kin.pose import FloatArray, invert_transform
from melfa.sim.debug.cell import DEFAULT_FLOOR_Z, Cell, Shape, Solid, Vec

LAND_EPS_MM = 1.0
"""A support this far above a part's bottom still counts as below it (round-off, a part
placed exactly on another)."""

OVERLAP_MM = 0.5
"""Footprints must overlap by more than this for one to rest on the other: two blocks set
side by side, touching, do not stack."""

TABLE = "table"
"""What a part standing on the table plane rests on."""


class HandChange(enum.Enum):
    CLOSE = "close"
    OPEN = "open"


@dataclass(frozen=True, slots=True)
class HandAction:
    """The gripper's hand closed or opened: when (simulated seconds since the run began),
    on which line of the user's text, where the tool was (`pose`: X, Y, Z, A, B, C of the
    TCP as P_CURR reads it), where the grip point was, and the part it took or let go
    (None: nothing). An open also says where the part came to rest (`landed`, the centre
    of its bottom face), how far it fell (`drop`, mm) and on what (`on`)."""

    change: HandChange
    time: float
    line: int | None
    hand: int
    pose: tuple[float, float, float, float, float, float]
    grip: Vec
    part: str | None
    landed: Vec | None = None
    drop: float | None = None
    on: str | None = None

    def to_json(self) -> dict[str, object]:
        return {
            "change": self.change.value,
            "time": self.time,
            "line": self.line,
            "hand": self.hand,
            "pose": list(self.pose),
            "grip": list(self.grip),
            "part": self.part,
            "landed": list(self.landed) if self.landed is not None else None,
            "drop": self.drop,
            "on": self.on,
        }


@dataclass(frozen=True, slots=True)
class PartState:
    """Where a part is: the centre of its bottom face, its heading, whether the gripper
    holds it, and what it stands on (`TABLE`, a fixture, conveyor or part; None: held)."""

    name: str
    position: Vec
    rz: float
    held: bool
    on: str | None

    def to_json(self) -> dict[str, object]:
        return {
            "name": self.name,
            "position": list(self.position),
            "rz": self.rz,
            "held": self.held,
            "on": self.on,
        }


@dataclass(frozen=True, slots=True)
class Snapshot:
    """The loose parts (not held) from `time` on, and the one held (if any): the part and
    its centre's frame in the flange's (4×4)."""

    time: float
    loose: tuple[Solid, ...]
    held: str | None
    carried: tuple[Solid, FloatArray] | None = None


class CellWorld:
    """The parts of a `Cell` during one run (see the module's docstring)."""

    def __init__(self, cell: Cell) -> None:
        self.cell = cell
        self.floor = cell.floor_z if cell.floor_z is not None else DEFAULT_FLOOR_Z
        self._fixed = cell.obstacles
        self._conveyor_names = {c.name for c in cell.conveyors}
        self._parts: dict[str, Solid] = {p.name: p for p in cell.parts}
        self._on: dict[str, str] = {}
        self._held: str | None = None
        self._grip_rel: FloatArray | None = None  # held part's centre frame in the flange's
        self._outputs: dict[int, int] = {}
        self.time = 0.0
        self.actions: list[HandAction] = []
        self.snapshots: list[Snapshot] = []
        for name in sorted(self._parts, key=lambda n: self._parts[n].position[2]):
            self._land(name)
        self._snap()

    # ------------------------------------------------------------------ the hand
    def grip_point(self, flange: FloatArray) -> Vec:
        p = flange @ np.array([0.0, 0.0, self.cell.gripper.grip, 1.0])
        return (float(p[0]), float(p[1]), float(p[2]))

    def close(
        self, time: float, flange: FloatArray, pose: tuple[float, ...], line: int | None
    ) -> HandAction:
        """The gripper's hand closes with the flange at `flange` (world 4×4)."""
        self.advance(time)
        grip = self.grip_point(flange)
        taken: str | None = self._held
        if taken is None:
            best = self.cell.gripper.tolerance
            for name, part in self._parts.items():
                d = math.dist(part.centre, grip)
                if d <= best:
                    taken, best = name, d
            if taken is not None:
                self._held = taken
                self._grip_rel = invert_transform(flange) @ _centre_frame(self._parts[taken])
                self._on.pop(taken, None)
                self._settle()
                self._snap()
        action = HandAction(
            HandChange.CLOSE, time, line, self.cell.gripper.hand, _six(pose), grip, taken
        )
        self.actions.append(action)
        return action

    def open(
        self, time: float, flange: FloatArray, pose: tuple[float, ...], line: int | None
    ) -> HandAction:
        """The gripper's hand opens: what it held drops onto what is below it."""
        self.advance(time)
        grip = self.grip_point(flange)
        name = self._held
        hand = self.cell.gripper.hand
        if name is None or self._grip_rel is None:
            action = HandAction(HandChange.OPEN, time, line, hand, _six(pose), grip, None)
        else:
            frame = flange @ self._grip_rel
            part = self._parts[name]
            rz = math.degrees(math.atan2(frame[1, 0], frame[0, 0]))
            cx, cy, cz = (float(v) for v in frame[:3, 3])
            bottom = cz - part.height / 2
            self._parts[name] = part.moved((cx, cy, bottom), rz)
            self._held, self._grip_rel = None, None
            self._land(name)
            landed = self._parts[name].position
            action = HandAction(
                HandChange.OPEN,
                time,
                line,
                hand,
                _six(pose),
                grip,
                name,
                landed,
                max(0.0, bottom - landed[2]),
                self._on.get(name),
            )
            self._snap()
        self.actions.append(action)
        return action

    # ------------------------------------------------------------------ devices
    def set_output(self, time: float, bit: int, value: int) -> None:
        """An output changed at `time` (conveyors start or stop)."""
        self.advance(time)
        self._outputs[bit] = value

    def advance(self, time: float) -> None:
        """Run the conveyors up to `time`."""
        dt = time - self.time
        if dt <= 0:
            return
        self.time = time
        moved = False
        for belt in self.cell.conveyors:
            if not self._outputs.get(belt.output, 0):
                continue
            bx, by, _ = belt.position
            hx, hy = belt.size[0] / 2, belt.size[1] / 2
            for name, part in self._parts.items():
                if self._on.get(name) != belt.name:
                    continue
                x, y, z = part.position
                nx = min(max(x + belt.velocity[0] * dt, bx - hx), bx + hx)
                ny = min(max(y + belt.velocity[1] * dt, by - hy), by + hy)
                if (nx, ny) != (x, y):
                    self._parts[name] = part.moved((nx, ny, z))
                    moved = True
        if moved:
            self._snap()

    @property
    def running(self) -> bool:
        """A conveyor is on (parts may still move while the program waits)."""
        return any(self._outputs.get(c.output, 0) for c in self.cell.conveyors)

    def inputs(self, flange: FloatArray | None = None) -> dict[int, int]:
        """Every sensor's input bit: 1 while a part's centre is in its region (a held part
        counts when `flange` says where it is)."""
        centres = [p.centre for n, p in self._parts.items() if n != self._held]
        if self._held is not None and self._grip_rel is not None and flange is not None:
            c = (flange @ self._grip_rel)[:3, 3]
            centres.append((float(c[0]), float(c[1]), float(c[2])))
        out: dict[int, int] = {}
        for s in self.cell.sensors:
            out[s.input] = out.get(s.input, 0) | int(any(s.sees(c) for c in centres))
        return out

    # ------------------------------------------------------------------ reading
    @property
    def held(self) -> str | None:
        return self._held

    def parts(self, flange: FloatArray | None = None) -> list[PartState]:
        """Every part now, in the cell's order (a held part where `flange` puts it)."""
        out = []
        for p in self.cell.parts:
            part = self._parts[p.name]
            if p.name == self._held and self._grip_rel is not None and flange is not None:
                frame = flange @ self._grip_rel
                c = frame[:3, 3]
                rz = math.degrees(math.atan2(frame[1, 0], frame[0, 0]))
                bottom = (float(c[0]), float(c[1]), float(c[2]) - part.height / 2)
                out.append(PartState(p.name, bottom, rz, True, None))
            else:
                held = p.name == self._held
                out.append(PartState(p.name, part.position, part.rz, held, self._on.get(p.name)))
        return out

    def loose_at(self, time: float) -> Snapshot:
        """The loose parts as they were at `time` (the snapshot in force then)."""
        found = self.snapshots[0]
        for s in self.snapshots:
            if s.time > time:
                break
            found = s
        return found

    # ------------------------------------------------------------------ helpers
    def _snap(self) -> None:
        loose = tuple(p for n, p in self._parts.items() if n != self._held)
        carried = None
        if self._held is not None and self._grip_rel is not None:
            carried = (self._parts[self._held], self._grip_rel)
        snap = Snapshot(self.time, loose, self._held, carried)
        if self.snapshots and self.snapshots[-1].time == self.time:
            self.snapshots[-1] = snap
        else:
            self.snapshots.append(snap)

    def _land(self, name: str) -> None:
        """Drop part `name` straight down onto the highest support under it."""
        part = self._parts[name]
        best, on = self.floor, TABLE
        supports = list(self._fixed) + [
            p for n, p in self._parts.items() if n != name and n != self._held
        ]
        for s in supports:
            top = s.top
            # below the part, or reaching into it (pushed in: it comes to rest on top)
            if best < top < part.top + LAND_EPS_MM and footprints_overlap(part, s):
                best, on = top, s.name
        x, y, _ = part.position
        self._parts[name] = part.moved((x, y, best))
        self._on[name] = on

    def _settle(self) -> None:
        """Parts whose support was taken away drop (lowest first)."""
        while True:
            loose = [n for n in self._parts if n != self._held]
            known = set(loose) | {s.name for s in self._fixed} | {TABLE}
            orphans = sorted(
                (n for n in loose if self._on.get(n) not in known),
                key=lambda n: self._parts[n].position[2],
            )
            if not orphans:
                return
            self._land(orphans[0])


def _six(pose: tuple[float, ...]) -> tuple[float, float, float, float, float, float]:
    x, y, z, a, b, c = (float(v) for v in pose[:6])
    return (x, y, z, a, b, c)


def _centre_frame(part: Solid) -> FloatArray:
    t = np.eye(4)
    r = math.radians(part.rz)
    t[:2, :2] = [[math.cos(r), -math.sin(r)], [math.sin(r), math.cos(r)]]
    t[:3, 3] = part.centre
    return t


def footprints_overlap(a: Solid, b: Solid, margin: float = OVERLAP_MM) -> bool:
    """Whether the shapes of `a` and `b` seen from above overlap by more than `margin`."""
    if a.shape is Shape.CYLINDER and b.shape is Shape.CYLINDER:
        d = math.dist(a.position[:2], b.position[:2])
        return d < a.size[0] / 2 + b.size[0] / 2 - margin
    if a.shape is Shape.CYLINDER or b.shape is Shape.CYLINDER:
        circle, rect = (a, b) if a.shape is Shape.CYLINDER else (b, a)
        lx, ly = _local(rect, circle.position[0], circle.position[1])
        hx, hy = rect.size[0] / 2, rect.size[1] / 2
        inside = abs(lx) < hx and abs(ly) < hy
        nx, ny = min(max(lx, -hx), hx), min(max(ly, -hy), hy)
        return inside or math.hypot(lx - nx, ly - ny) < circle.size[0] / 2 - margin
    for rect in (a, b):  # separating axes: each rectangle's two sides
        r = math.radians(rect.rz)
        for ux, uy in ((math.cos(r), math.sin(r)), (-math.sin(r), math.cos(r))):
            pa = _project(a, ux, uy)
            pb = _project(b, ux, uy)
            if min(pa[1], pb[1]) - max(pa[0], pb[0]) <= margin:
                return False
    return True


def _local(rect: Solid, x: float, y: float) -> tuple[float, float]:
    r = math.radians(rect.rz)
    dx, dy = x - rect.position[0], y - rect.position[1]
    return (dx * math.cos(r) + dy * math.sin(r), -dx * math.sin(r) + dy * math.cos(r))


def _project(rect: Solid, ux: float, uy: float) -> tuple[float, float]:
    r = math.radians(rect.rz)
    c, s = math.cos(r), math.sin(r)
    hx, hy = rect.size[0] / 2, rect.size[1] / 2
    centre = rect.position[0] * ux + rect.position[1] * uy
    half = abs(hx * (c * ux + s * uy)) + abs(hy * (-s * ux + c * uy))
    return (centre - half, centre + half)
