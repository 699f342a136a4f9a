"""Planned motions sampled in time: joint moves, Cartesian paths, sequences, and stops.

A plan is built once (by `melfa.sim.motion`), then sampled at any time ``t``:
``plan.sample(t) -> Joints``; ``plan.stopped(t)`` is the decelerating stop from ``t``
(time origin moved to ``t``). `Frames` (base and tool) turn TCP poses into flange poses.
"""

from __future__ import annotations

import enum
from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from melfa.kin import (
    DEFAULT_INTERFERENCE,
    Configuration,
    Interference,
    Joints,
    Pose,
    fk,
    fk_matrix,
    ik_batch,
    pose_to_matrix,
    unwrap_j6,
)
from melfa.kin.pose import FloatArray, invert_transform, matrix_to_pose
from melfa.sim.paths import Path
from melfa.sim.timing import StopTiming, Timing

__all__ = [
    "ArcPlan",
    "Frames",
    "JointPlan",
    "MoveKind",
    "PathPlan",
    "Plan",
    "SequencePlan",
]


class MoveKind(enum.Enum):
    JOINT = "MOV"
    LINEAR = "MVS"
    ARC = "MVR"
    CIRCLE = "MVC"
    ARCH = "MVA"
    SEQUENCE = "sequence"
    STOP = "stop"


@dataclass(frozen=True, slots=True)
class Frames:
    """The active TOOL and BASE (None = identity) and which interference rows apply."""

    tool: Pose | None = None
    base: Pose | None = None
    interference: Interference = DEFAULT_INTERFERENCE

    def pose(self, joints: Sequence[float]) -> Pose:
        """TCP pose (with flags) of a joint vector."""
        return fk(joints, self.tool, self.base)

    def tcp_matrix(self, joints: Sequence[float]) -> FloatArray:
        return fk_matrix(joints, self.tool, self.base)

    def to_flange(self, tcp: FloatArray) -> FloatArray:
        """World TCP transforms (N, 4, 4) -> robot-base flange transforms."""
        out = tcp
        if self.base is not None:
            out = invert_transform(pose_to_matrix(self.base)) @ out
        if self.tool is not None:
            out = out @ invert_transform(pose_to_matrix(self.tool))
        return out


class Plan(ABC):
    """A planned motion sampled at t seconds from its start (clamped to [0, duration])."""

    kind: MoveKind
    start_joints: Joints
    end_joints: Joints

    @property
    @abstractmethod
    def duration(self) -> float: ...

    @abstractmethod
    def sample(self, t: float) -> Joints:
        """Joints (deg) at t seconds after the plan started."""

    def sample_many(self, ts: FloatArray) -> FloatArray:
        """Joints (N, 6) at each of the times `ts`: `sample` for many times in one call
        (a path's IK is solved for all of them at once)."""
        return np.array([tuple(self.sample(float(t))) for t in ts], dtype=float).reshape(-1, 6)

    @abstractmethod
    def stopped(self, t: float) -> Plan:
        """The decelerating stop begun at t: a new plan whose time 0 is t."""


class _PathLike(Plan):
    """Plans moving along one geometric parameter s in [0, 1]."""

    timing: Timing

    @property
    def duration(self) -> float:
        return self.timing.duration

    @abstractmethod
    def at_s(self, s: float) -> Joints: ...

    def sample(self, t: float) -> Joints:
        if t >= self.timing.duration:
            return self.end_joints
        return self.at_s(self.timing.s(t))

    def sample_many(self, ts: FloatArray) -> FloatArray:
        d = self.timing.duration
        return self.at_s_many(np.array([self.timing.s(t) if t < d else 1.0 for t in ts.tolist()]))

    def at_s_many(self, s: FloatArray) -> FloatArray:
        """`at_s` for many parameters (N,) -> joints (N, 6)."""
        return np.array([tuple(self.at_s(float(v))) for v in s], dtype=float).reshape(-1, 6)

    def stopped(self, t: float) -> Plan:
        s0, v0 = self.timing.state(t)
        return _StoppingPlan(self, StopTiming(s0, v0, self.timing.decel_rate))


class _StoppingPlan(Plan):
    kind = MoveKind.STOP

    def __init__(self, base: _PathLike, timing: StopTiming) -> None:
        self.base = base
        self.timing = timing
        self.start_joints = base.at_s(timing.s0)
        self.end_joints = base.at_s(timing.s(timing.duration))

    @property
    def duration(self) -> float:
        return self.timing.duration

    def sample(self, t: float) -> Joints:
        return self.end_joints if t >= self.duration else self.base.at_s(self.timing.s(t))

    def stopped(self, t: float) -> Plan:
        s = self.timing.s(t)
        v = max(0.0, self.timing.v0 - self.timing.decel * t)
        return _StoppingPlan(self.base, StopTiming(s, v, self.timing.decel))


class JointPlan(_PathLike):
    """Joint interpolation: every joint moves proportionally, synchronised to the slowest."""

    kind = MoveKind.JOINT

    def __init__(self, start: Joints, end: Joints, timing: Timing) -> None:
        self.start_joints = start
        self.end_joints = end
        self.timing = timing
        self._q0 = np.asarray(start, dtype=float)
        self._dq = np.asarray(end, dtype=float) - self._q0

    def at_s(self, s: float) -> Joints:
        return Joints.of(self._q0 + s * self._dq)

    def at_s_many(self, s: FloatArray) -> FloatArray:
        return np.asarray(self._q0 + s[:, None] * self._dq, dtype=float)


class PathPlan(_PathLike):
    """A Cartesian path (line or arc) with joints from IK at each sample."""

    def __init__(
        self,
        kind: MoveKind,
        path: Path,
        frames: Frames,
        config: Configuration,
        table_s: FloatArray,
        table_q: FloatArray,
        timing: Timing,
    ) -> None:
        self.kind = kind
        self.path = path
        self.frames = frames
        self.config = config
        self.table_s = table_s
        self.table_q = table_q
        self.timing = timing
        self.start_joints = Joints.of(table_q[0])
        self.end_joints = Joints.of(table_q[-1])

    def at_s(self, s: float) -> Joints:
        if s <= 0.0:
            return self.start_joints
        if s >= 1.0:
            return self.end_joints
        near = np.array([np.interp(s, self.table_s, self.table_q[:, j]) for j in range(6)])
        flange = self.frames.to_flange(self.path.at(np.array([s])))
        q = ik_batch(flange, self.config, near[0], near[3])[0]
        if np.isnan(q[0]):  # cannot happen on a checked path; fall back to the table
            return Joints.of(near)
        q[5] = unwrap_j6(q[5:6], float(near[5]))[0]
        return Joints.of(q)

    def at_s_many(self, s: FloatArray) -> FloatArray:
        near = np.column_stack([np.interp(s, self.table_s, self.table_q[:, j]) for j in range(6)])
        out = near.copy()
        out[s <= 0.0] = self.start_joints
        out[s >= 1.0] = self.end_joints
        inner = (s > 0.0) & (s < 1.0)
        if inner.any():
            flange = self.frames.to_flange(self.path.at(s[inner]))
            guess = near[inner]
            q = ik_batch(flange, self.config, guess[:, 0], guess[:, 3])
            bad = np.isnan(q[:, 0])  # cannot happen on a checked path; the table then
            q[bad] = guess[bad]
            q[:, 5] += 360.0 * np.round((guess[:, 5] - q[:, 5]) / 360.0)
            out[inner] = q
        return out

    def tcp_pose(self, s: float) -> Pose:
        """The TCP pose on the path at parameter s (for tests and the 3D view)."""
        return matrix_to_pose(self.path.at(np.array([s]))[0])


ArcPlan = PathPlan


class SequencePlan(Plan):
    """Plans run one after the other (approach + arc, MVA's lift/traverse/lower)."""

    kind = MoveKind.SEQUENCE

    def __init__(self, parts: Sequence[Plan], kind: MoveKind = MoveKind.SEQUENCE) -> None:
        if not parts:
            raise ValueError("a sequence needs at least one plan")
        self.parts = tuple(parts)
        self.kind = kind
        self.start_joints = self.parts[0].start_joints
        self.end_joints = self.parts[-1].end_joints
        self._offsets = np.cumsum([0.0] + [p.duration for p in self.parts])

    @property
    def duration(self) -> float:
        return float(self._offsets[-1])

    def _locate(self, t: float) -> tuple[int, float]:
        i = int(np.searchsorted(self._offsets, t, side="right")) - 1
        i = min(max(i, 0), len(self.parts) - 1)
        return i, t - float(self._offsets[i])

    def sample(self, t: float) -> Joints:
        if t >= self.duration:
            return self.end_joints
        i, local = self._locate(t)
        return self.parts[i].sample(local)

    def sample_many(self, ts: FloatArray) -> FloatArray:
        ts = np.asarray(ts, dtype=float)
        out = np.empty((len(ts), 6))
        which = np.clip(
            np.searchsorted(self._offsets, ts, side="right") - 1, 0, len(self.parts) - 1
        )
        for i in np.unique(which).tolist():
            rows = which == i
            out[rows] = self.parts[i].sample_many(ts[rows] - float(self._offsets[i]))
        out[ts >= self.duration] = self.end_joints
        return out

    def stopped(self, t: float) -> Plan:
        i, local = self._locate(min(t, self.duration))
        return self.parts[i].stopped(local)
