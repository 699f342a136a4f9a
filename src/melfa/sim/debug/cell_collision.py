"""Collisions of the arm's links and the gripper (capsules, `melfa.kin.capsules`) and of the
part the gripper carries (points on its rims or corners) with the cell's fixtures, parts
and table, along a move, densely enough that nothing is skipped.

A capsule is checked as spheres along its axis (spaced a quarter of its radius apart: the
union is within 1 mm of the true capsule for the arm's radii). Along a move, the check
starts from the coarse samples pre-flight already takes and bounds how far any point of
each capsule can move between two of them (each joint's turn times how far the capsule is
from that joint's axis, `ArmBodies.moved`). Where that
bound could reach an obstacle, the interval is sampled again so that no point moves more
than `FINE_MM` between samples: a plate `FINE_MM` thick (5 mm) is never skipped. This
assumes each joint moves monotonically between two coarse samples (joint moves do; the
samples of a linear move are a few milliseconds of motion apart).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from melfa.kin import capsules
from melfa.kin.pose import FloatArray
from melfa.kin.solver import fk_batch
from melfa.sim.debug.cell import Gripper, Shape, Solid
from melfa.sim.debug.cell_world import TABLE

FINE_MM = 5.0
"""No point of the arm moves more than this between two checked samples near an obstacle."""

SPHERES_PER_RADIUS = 4
"""Spheres along a capsule's axis per radius of length (spacing r/4: within 1 mm)."""


@dataclass(frozen=True, slots=True)
class Collision:
    """`body` (a link, the gripper, or the part it carries when `carried`) inside
    `obstacle` (a fixture, part or the table) during the `move`-th move from `start` to
    `end` (simulated seconds since the run began), at most `depth` mm deep, caused by
    `line` of the user's text."""

    body: str
    obstacle: str
    line: int | None
    move: int
    start: float
    end: float
    depth: float
    carried: bool = False

    def to_json(self) -> dict[str, object]:
        return {
            "body": self.body,
            "obstacle": self.obstacle,
            "line": self.line,
            "move": self.move,
            "start": self.start,
            "end": self.end,
            "depth": self.depth,
            "carried": self.carried,
        }


class ArmBodies:
    """The arm's capsules with the cell's gripper, in the world frame (`base`: BASE)."""

    def __init__(self, gripper: Gripper | None, base: FloatArray | None = None) -> None:
        length = gripper.length if gripper is not None else 0.0
        radius = gripper.radius if gripper is not None and length > 0 else None
        self.base = base
        self.tool_length = length if radius is not None else 0.0
        self.names = capsules.names(radius is not None)
        self.radii = capsules.radii(radius)
        self.reach = capsules.reach(self.tool_length, radius)
        # sphere positions along each capsule (fractions of its axis), capsule by capsule
        starts, ends = capsules.segments(np.zeros((1, 6)), base=None, tool_length=self.tool_length)
        lengths = np.linalg.norm(ends[0] - starts[0], axis=1)
        fractions: list[FloatArray] = []
        for length_c, r in zip(lengths, self.radii, strict=True):
            k = max(2, math.ceil(float(length_c) * SPHERES_PER_RADIUS / float(r)) + 1)
            fractions.append(np.linspace(0.0, 1.0, k))
        self._fractions = fractions
        self._half = lengths / 2

    def clearance(
        self,
        q: FloatArray,
        obstacles: Sequence[Solid],
        floor: float | None,
        threshold: float = 0.0,
    ) -> FloatArray:
        """(N, C, O): how far each capsule is from each obstacle (the table last when
        `floor` is given), negative when inside, for joint rows q (N, 6) in degrees.

        Where a capsule stays at least `threshold` away from an obstacle over all N rows
        (told by bounding spheres), the value is only a lower bound of at least that."""
        return self.clearance_of(self.place(q), obstacles, floor, threshold)

    def place(self, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """The capsules' ends and the joints' axes for joint rows q (N, 6)."""
        return capsules.placed(q, base=self.base, tool_length=self.tool_length)

    def moved(self, q: FloatArray, placed: tuple[FloatArray, ...]) -> FloatArray:
        """(N-1, C): how far any point of each capsule can move between rows k and k+1,
        when each joint moves monotonically in between."""
        turn = np.abs(np.radians(np.diff(q, axis=0)))  # (N-1, 6)
        chain = turn @ self.reach  # the bound from link lengths alone
        starts, ends, origins, dirs = placed
        far = capsules.axis_distance(starts, ends, origins, dirs) + self.radii  # (N, 6, C)
        far = np.where(self.reach[None] > 0, np.maximum(far[:-1], far[1:]), 0.0)
        total = turn.sum(axis=1, keepdims=True)
        # points drift from an axis by at most what they move: L <= sum|dq| (R + L)
        tight = np.einsum("nj,njc->nc", turn, far) / np.maximum(1.0 - total, 1e-9)
        return np.where(total < 0.5, np.minimum(tight, chain), chain)

    def clearance_of(
        self,
        placed: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
        obstacles: Sequence[Solid],
        floor: float | None,
        threshold: float = 0.0,
    ) -> FloatArray:
        """`clearance` of capsules already placed (`place`)."""
        starts, ends = placed[0], placed[1]
        n, c_count = starts.shape[0], len(self.names)
        mids = (starts + ends) / 2  # (N, C, 3)
        out = np.empty((n, c_count, len(obstacles) + (floor is not None)))
        for o, solid in enumerate(obstacles):
            # bounding spheres of each capsule and of the solid
            sx, sy, sz = solid.size
            centre = np.array(solid.centre)
            bound = (
                np.linalg.norm(mids - centre, axis=2)
                - self._half
                - self.radii
                - 0.5 * math.sqrt(sx * sx + sy * sy + sz * sz)
            )
            out[:, :, o] = bound
            for c in np.nonzero(np.min(bound, axis=0) < threshold)[0].tolist():
                a, b = starts[:, c], ends[:, c]
                points = a[:, None] + (b - a)[:, None] * self._fractions[c][None, :, None]
                out[:, c, o] = np.min(_distance(points, solid), axis=1) - self.radii[c]
        if floor is not None:
            low = np.minimum(starts[..., 2], ends[..., 2]) - floor - self.radii
            low[:, 0] = np.inf  # the base stands on the table
            out[:, :, -1] = low
        return out


def move_collisions(
    bodies: ArmBodies,
    sample: Callable[[FloatArray], FloatArray],
    ts: FloatArray,
    q: FloatArray,
    obstacles: Sequence[Solid],
    floor: float | None,
    *,
    move: int,
    offset: float,
    line: int | None,
    carried: tuple[Solid, FloatArray] | None = None,
) -> tuple[list[Collision], int]:
    """Collisions along one move sampled at local times `ts` (joints `q`); `sample(ts)`
    gives the joints (N, 6) at any local times, `offset` turns local times into the run's.
    `carried` is the part the gripper holds and its centre's frame in the flange's: it is
    checked too (its corners and rims; touching is not a collision, `CONTACT_MM`).
    Returns the collisions and how many samples were checked exactly."""
    names = [s.name for s in obstacles] + ([TABLE] if floor is not None else [])
    if not names:
        return [], len(ts)
    held = _Carried(carried, bodies) if carried is not None else None
    body_names = list(bodies.names) + ([held.part.name] if held is not None else [])

    def clearance(rows: FloatArray, threshold: float, placed: Any = None) -> FloatArray:
        placed = placed if placed is not None else bodies.place(rows)
        out = bodies.clearance_of(placed, obstacles, floor, threshold)
        if held is None:
            return out
        return np.concatenate([out, held.clearance(rows, obstacles, floor)[:, None]], axis=1)

    placed = bodies.place(q)
    moved = bodies.moved(q, placed)  # (N-1, C)
    if held is not None:
        moved = np.concatenate([moved, held.moved(q, placed)[:, None]], axis=1)
    clear = clearance(q, float(np.max(moved, initial=0.0)), placed)
    times = [ts]
    rows = [clear]
    if len(ts) > 1:
        margin = np.min(clear[:-1], axis=2) - moved  # could an obstacle be reached?
        fine: list[FloatArray] = []
        for k in np.nonzero(np.min(margin, axis=1) < 0)[0].tolist():
            m = math.ceil(float(np.max(moved[k])) / FINE_MM)
            if m > 1:
                fine.append(ts[k] + (ts[k + 1] - ts[k]) * np.arange(1, m) / m)
        if fine:
            fine_t = np.concatenate(fine)
            rows.append(clearance(sample(fine_t), 0.0))
            times.append(fine_t)
    all_t = np.concatenate(times)
    order = np.argsort(all_t, kind="stable")
    all_t = all_t[order]
    all_clear = np.concatenate(rows, axis=0)[order]
    out: list[Collision] = []
    hit = all_clear < 0
    for c, o in zip(*np.nonzero(np.any(hit, axis=0)), strict=True):
        mask = hit[:, c, o]
        for a, b in _runs(mask):
            depth = float(-np.min(all_clear[a:b, c, o]))
            part = bool(c >= len(bodies.names))
            out.append(
                Collision(
                    body_names[c],
                    names[o],
                    line,
                    move,
                    float(all_t[a] + offset),
                    float(all_t[b - 1] + offset),
                    depth + CONTACT_MM if part else depth,
                    part,
                )
            )
    out.sort(key=lambda col: col.start)
    return out, len(all_t)


CONTACT_MM = 0.5
"""A carried part this far into something only touches it (set down on a block, beside
one): not a collision."""


class _Carried:
    """The part the gripper holds, as points on its rims or corners (top and bottom)."""

    def __init__(self, carried: tuple[Solid, FloatArray], bodies: ArmBodies) -> None:
        self.part, self.rel = carried
        self.bodies = bodies
        sx, sy, sz = self.part.size
        if self.part.shape is Shape.CYLINDER:
            a = np.linspace(0, 2 * math.pi, 12, endpoint=False)
            ring = np.column_stack([sx / 2 * np.cos(a), sx / 2 * np.sin(a)])
        else:
            ring = np.array([[x, y] for x in (-sx / 2, sx / 2) for y in (-sy / 2, sy / 2)])
        ring = np.vstack([ring, [[0.0, 0.0]]])
        pts = [
            np.column_stack([ring, np.full(len(ring), z), np.ones(len(ring))])
            for z in (-sz / 2, sz / 2)
        ]
        self.points = np.vstack(pts)  # (K, 4) in the part's centre frame
        reach = float(np.linalg.norm(self.rel[:3, 3])) + 0.5 * math.sqrt(
            sx * sx + sy * sy + sz * sz
        )
        self.reach = reach

    def clearance(
        self, q: FloatArray, obstacles: Sequence[Solid], floor: float | None
    ) -> FloatArray:
        """(N, O): the deepest any point of the part is in each obstacle, plus `CONTACT_MM`."""
        flange = fk_batch(q)
        if self.bodies.base is not None:
            flange = self.bodies.base @ flange
        world = (flange @ self.rel @ self.points.T).transpose(0, 2, 1)[..., :3]  # (N, K, 3)
        cols = [np.min(_distance(world, s), axis=1) for s in obstacles]
        if floor is not None:
            cols.append(np.min(world[..., 2], axis=1) - floor)
        return np.stack(cols, axis=1) + CONTACT_MM

    def moved(self, q: FloatArray, placed: Any) -> FloatArray:
        """How far any point of the part can move between samples (as `ArmBodies.moved`:
        each joint's turn times the part's distance from that joint's axis)."""
        turn = np.abs(np.radians(np.diff(q, axis=0)))  # (N-1, 6)
        flange = fk_batch(q)
        if self.bodies.base is not None:
            flange = self.bodies.base @ flange
        half = self.part.size[2] / 2
        ends = flange @ self.rel @ np.array([[0, 0, -half, 1.0], [0, 0, half, 1.0]]).T
        a, b = ends[:, :3, 0][:, None], ends[:, :3, 1][:, None]  # (N, 1, 3)
        sx, sy = self.part.size[0], self.part.size[1]
        far = capsules.axis_distance(a, b, placed[2], placed[3])[..., 0] + 0.5 * math.hypot(sx, sy)
        far = np.maximum(far[:-1], far[1:])  # (N-1, 6)
        total = turn.sum(axis=1)
        tight = np.einsum("nj,nj->n", turn, far) / np.maximum(1.0 - total, 1e-9)
        chain = total * (float(np.max(self.bodies.reach)) + self.reach)  # the arm at full stretch
        return np.asarray(np.where(total < 0.5, tight, chain))


def _runs(mask: npt.NDArray[np.bool_]) -> list[tuple[int, int]]:
    """[start, end) index ranges where `mask` holds."""
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    starts = np.nonzero(edges == 1)[0]
    ends = np.nonzero(edges == -1)[0]
    return list(zip(starts.tolist(), ends.tolist(), strict=True))


def _distance(points: FloatArray, solid: Solid) -> FloatArray:
    """Signed distance (N, S) from points (N, S, 3) to `solid` (negative inside)."""
    x, y, z = solid.position
    half_h = solid.size[2] / 2
    dz = np.abs(points[..., 2] - (z + half_h)) - half_h
    dx = points[..., 0] - x
    dy = points[..., 1] - y
    if solid.shape is Shape.CYLINDER:
        radial = np.hypot(dx, dy) - solid.size[0] / 2
        outside = np.hypot(np.maximum(radial, 0.0), np.maximum(dz, 0.0))
        inside = np.minimum(np.maximum(radial, dz), 0.0)
        return np.asarray(outside + inside)
    if solid.rz:
        r = math.radians(solid.rz)
        dx, dy = dx * math.cos(r) + dy * math.sin(r), -dx * math.sin(r) + dy * math.cos(r)
    qx = np.abs(dx) - solid.size[0] / 2
    qy = np.abs(dy) - solid.size[1] / 2
    outside = np.sqrt(
        np.maximum(qx, 0.0) ** 2 + np.maximum(qy, 0.0) ** 2 + np.maximum(dz, 0.0) ** 2
    )
    inside = np.minimum(np.maximum(np.maximum(qx, qy), dz), 0.0)
    return np.asarray(outside + inside)
