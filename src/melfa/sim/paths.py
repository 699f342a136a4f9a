"""Geometry of Cartesian paths: lines and arcs of the TCP with slerped orientation.

A `Path` maps the path parameter s in [0, 1] to 4x4 TCP poses (`at`); `Line` and `Arc` are
the two kinds; `circle_through` and `ccw_angle` build arcs from points. Pure numpy.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from melfa.kin import KinematicsError
from melfa.kin.pose import FloatArray


class IllegalMove(KinematicsError):
    """The move's geometry is impossible (collinear arc points, flags changing in MVS, ...)."""


def log_rot(r: FloatArray) -> FloatArray:
    """Rotation vector (axis × angle, radians) of a rotation matrix."""
    cos = (float(np.trace(r)) - 1.0) / 2.0
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]]) / 2.0
    sin = float(np.linalg.norm(v))
    angle = math.atan2(sin, cos)
    if sin > 1e-9:
        return np.asarray(v / sin * angle, dtype=float)
    if cos > 0:
        return np.zeros(3)
    # angle ≈ π: axis from the symmetric part
    m = (r + np.eye(3)) / 2.0
    k = int(np.argmax(np.diag(m)))
    axis = m[:, k] / math.sqrt(max(m[k, k], 1e-300))
    return np.asarray(axis / np.linalg.norm(axis) * math.pi, dtype=float)


def exp_rot(rv: FloatArray) -> FloatArray:
    """Rotation matrices (N, 3, 3) from rotation vectors (N, 3) (Rodrigues)."""
    theta = np.linalg.norm(rv, axis=1)
    safe = np.where(theta > 1e-12, theta, 1.0)
    k = rv / safe[:, None]
    kx = np.zeros((rv.shape[0], 3, 3))
    kx[:, 0, 1], kx[:, 0, 2] = -k[:, 2], k[:, 1]
    kx[:, 1, 0], kx[:, 1, 2] = k[:, 2], -k[:, 0]
    kx[:, 2, 0], kx[:, 2, 1] = -k[:, 1], k[:, 0]
    s = np.sin(theta)[:, None, None]
    c = (1.0 - np.cos(theta))[:, None, None]
    return np.asarray(np.eye(3) + s * kx + c * (kx @ kx), dtype=float)


@dataclass(frozen=True)
class Orientation:
    """Piecewise slerp through key rotations placed at path fractions `knots`."""

    knots: tuple[float, ...]
    rots: tuple[FloatArray, ...]
    steps: tuple[FloatArray, ...] = field(init=False)

    def __post_init__(self) -> None:
        steps = tuple(log_rot(self.rots[i].T @ self.rots[i + 1]) for i in range(len(self.rots) - 1))
        object.__setattr__(self, "steps", steps)

    @property
    def total_angle_deg(self) -> float:
        return math.degrees(sum(float(np.linalg.norm(s)) for s in self.steps))

    def at(self, s: FloatArray) -> FloatArray:
        out = np.empty((s.shape[0], 3, 3))
        seg = np.clip(np.searchsorted(self.knots, s, side="right") - 1, 0, len(self.steps) - 1)
        for i in np.unique(seg):
            rows = seg == i
            lo, hi = self.knots[i], self.knots[i + 1]
            f = np.clip((s[rows] - lo) / (hi - lo), 0.0, 1.0) if hi > lo else np.ones(rows.sum())
            out[rows] = self.rots[i] @ exp_rot(f[:, None] * self.steps[i][None, :])
        return out


class Path(ABC):
    orientation: Orientation

    @property
    @abstractmethod
    def length(self) -> float:
        """TCP path length, mm."""

    @abstractmethod
    def positions(self, s: FloatArray) -> FloatArray: ...

    def at(self, s: FloatArray) -> FloatArray:
        """World TCP transforms (N, 4, 4) at path parameters s (N,)."""
        out = np.zeros((s.shape[0], 4, 4))
        out[:, :3, :3] = self.orientation.at(s)
        out[:, :3, 3] = self.positions(s)
        out[:, 3, 3] = 1.0
        return out


class Line(Path):
    def __init__(self, p0: FloatArray, p1: FloatArray, orientation: Orientation) -> None:
        self.p0, self.p1, self.orientation = p0, p1, orientation

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.p1 - self.p0))

    def positions(self, s: FloatArray) -> FloatArray:
        return np.asarray(self.p0 + s[:, None] * (self.p1 - self.p0), dtype=float)


class Arc(Path):
    """Arc about `centre` in the plane (u, w), angle `sweep` (rad), radius r0 -> r1."""

    def __init__(
        self,
        centre: FloatArray,
        u: FloatArray,
        w: FloatArray,
        r0: float,
        r1: float,
        sweep: float,
        orientation: Orientation,
    ) -> None:
        self.centre, self.u, self.w = centre, u, w
        self.r0, self.r1, self.sweep = r0, r1, sweep
        self.orientation = orientation

    @property
    def length(self) -> float:
        return (self.r0 + self.r1) / 2.0 * abs(self.sweep)

    def positions(self, s: FloatArray) -> FloatArray:
        ang = s * self.sweep
        r = self.r0 + s * (self.r1 - self.r0)
        return np.asarray(
            self.centre
            + r[:, None] * (np.cos(ang)[:, None] * self.u + np.sin(ang)[:, None] * self.w),
            dtype=float,
        )

    def fraction_of(self, point: FloatArray) -> float:
        """Path fraction at which the arc passes the direction of `point`."""
        d = point - self.centre
        ang = math.atan2(float(d @ self.w), float(d @ self.u)) % (2.0 * math.pi)
        return ang / self.sweep if self.sweep else 0.0


def circle_through(
    p0: FloatArray, p1: FloatArray, p2: FloatArray
) -> tuple[FloatArray, FloatArray, float]:
    """(centre, unit normal, radius) of the circle through three points; normal makes
    p0 -> p1 -> p2 counter-clockwise."""
    a, b = p1 - p0, p2 - p0
    n = np.cross(a, b)
    nn = float(n @ n)
    if nn < 1e-9 * max(float(a @ a) * float(b @ b), 1e-12) or nn < 1e-12:
        raise IllegalMove("arc points are collinear or coincide: no circle through them")
    centre = p0 + (float(a @ a) * np.cross(b, n) + float(b @ b) * np.cross(n, a)) / (2.0 * nn)
    return centre, n / math.sqrt(nn), float(np.linalg.norm(p0 - centre))


def ccw_angle(centre: FloatArray, normal: FloatArray, p0: FloatArray, p: FloatArray) -> float:
    """Angle (0, 2π] from p0 to p about `normal`."""
    u = p0 - centre
    u = u / np.linalg.norm(u)
    w = np.cross(normal, u)
    d = p - centre
    ang = math.atan2(float(d @ w), float(d @ u)) % (2.0 * math.pi)
    return ang if ang > 1e-12 else 2.0 * math.pi
