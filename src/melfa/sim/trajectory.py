"""What the simulated arm did: timed samples of its joints, pose and hands, and the moves and
hand changes it made, in bounded ring buffers (the 3D view, the debugger and pre-flight read
them; a `MoveEvent`'s plan replays the move, fast runs included)."""

from __future__ import annotations

import enum
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

from melfa.kin import Joints, Pose
from melfa.sim.plans import MoveKind, Plan


class HandState(enum.Enum):
    OPEN = "open"
    CLOSED = "closed"


@dataclass(frozen=True, slots=True)
class TrajectorySample:
    """Where the arm was at `time`: joints (deg), TCP pose, hands 1..8 (None = never set)."""

    time: float
    joints: Joints
    pose: Pose
    hands: tuple[HandState | None, ...]
    line: int | None


@dataclass(frozen=True, slots=True)
class HandEvent:
    time: float
    hand: int
    state: HandState
    line: int | None


@dataclass(frozen=True, slots=True)
class MoveEvent:
    """A motion began at `time`; `plan.sample(t - time)` replays it (fast runs included)."""

    time: float
    kind: MoveKind
    plan: Plan
    line: int | None

    @property
    def end_time(self) -> float:
        return self.time + self.plan.duration


class TrajectoryRecorder:
    """Bounded ring buffers of samples and events (oldest dropped first)."""

    def __init__(self, max_samples: int = 20000, max_events: int = 5000) -> None:
        self._samples: deque[TrajectorySample] = deque(maxlen=max_samples)
        self._events: deque[HandEvent | MoveEvent] = deque(maxlen=max_events)
        self.listeners: list[Callable[[HandEvent | MoveEvent], None]] = []
        """Called with each event as it is added (the cell's parts follow the hand)."""

    def add_sample(self, sample: TrajectorySample) -> None:
        self._samples.append(sample)

    def add_event(self, event: HandEvent | MoveEvent) -> None:
        self._events.append(event)
        for listener in self.listeners:
            listener(event)

    @property
    def samples(self) -> list[TrajectorySample]:
        return list(self._samples)

    @property
    def events(self) -> list[HandEvent | MoveEvent]:
        return list(self._events)

    @property
    def moves(self) -> list[MoveEvent]:
        return [e for e in self._events if isinstance(e, MoveEvent)]

    @property
    def hand_events(self) -> list[HandEvent]:
        return [e for e in self._events if isinstance(e, HandEvent)]

    @property
    def last(self) -> TrajectorySample | None:
        return self._samples[-1] if self._samples else None

    def since(self, time: float) -> list[TrajectorySample]:
        """Samples at or after `time` (for streaming to a viewer)."""
        return [s for s in self._samples if s.time >= time]

    def clear(self) -> None:
        self._samples.clear()
        self._events.clear()
