"""Jog requests and the dead-man keeper shared by the event loop and the worker thread.

Hold-to-move rides on the controller's own dead-man [DOC S1 §5.2.59]: a JOG not renewed
within ~140 ms stops by itself. The keeper turns client heartbeats into JOG renewals one for
one: a heartbeat marks the jog *fresh* and queues at most one renewal; a renewal consumes the
freshness. No heartbeat, no JOG — so a released key, a hidden page, a dead socket *or a
stalled service* all end in the controller stopping the arm within its watchdog.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

from melfa.protocol import JOINT_NAMES, POSE_NAMES, JogMode
from melfa.service.errors import InvalidArgument
from melfa.service.events import Actor, JogFrame

_MODES = {JogFrame.TOOL: JogMode.TOOL, JogFrame.XYZ: JogMode.XYZ, JogFrame.JOINT: JogMode.JOINT}


@dataclass(frozen=True)
class JogRequest:
    """One axis of one frame in one direction.

    >>> JogRequest.make("tool", "x", "+")
    JogRequest(frame=<JogFrame.TOOL: 'tool'>, axis=0, direction=1)
    >>> JogRequest.make(JogFrame.JOINT, "J3", -1).label
    'joint J3-'
    """

    frame: JogFrame
    axis: int
    """0-based: X/J1 = 0 … C/J6 = 5."""
    direction: int

    @classmethod
    def make(cls, frame: JogFrame | str, axis: int | str, direction: int | str) -> JogRequest:
        """Check and normalise; `InvalidArgument` with a clear message on nonsense."""
        try:
            frame = JogFrame(frame) if isinstance(frame, str) else frame
        except ValueError:
            names = ", ".join(f.value for f in JogFrame)
            raise InvalidArgument(f"jog frame {frame!r} is not one of {names}", "frame") from None
        axes = JOINT_NAMES if frame is JogFrame.JOINT else POSE_NAMES
        if isinstance(axis, str):
            key = axis.strip().upper()
            if key not in axes:
                raise InvalidArgument(f"jog axis {axis!r} is not one of {', '.join(axes)}", "axis")
            index = axes.index(key)
        else:
            index = int(axis)
            if index not in range(len(axes)):
                raise InvalidArgument(f"jog axis {axis} is outside 0–{len(axes) - 1}", "axis")
        if isinstance(direction, str):
            sign = {"+": 1, "-": -1, "+1": 1, "-1": -1}.get(direction.strip())
            if sign is None:
                raise InvalidArgument(f"jog direction {direction!r} is not + or -", "direction")
        else:
            sign = int(direction)
            if sign not in (1, -1):
                raise InvalidArgument(f"jog direction {direction} is not +1 or -1", "direction")
        return cls(frame, index, sign)

    @property
    def mode(self) -> JogMode:
        return _MODES[self.frame]

    @property
    def axis_name(self) -> str:
        return (JOINT_NAMES if self.frame is JogFrame.JOINT else POSE_NAMES)[self.axis]

    @property
    def label(self) -> str:
        return f"{self.frame.value} {self.axis_name}{'+' if self.direction > 0 else '-'}"


class JogKeeper:
    """Who jogs what, and whether a fresh heartbeat allows one more JOG. Thread-safe."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.actor: Actor | None = None
        self.request: JogRequest | None = None
        self.command_id = 0
        self.fresh = False
        self.tick_queued = False
        self.last_heartbeat = 0.0
        self.last_sent = 0.0
        self.heartbeats = 0
        self.renewals = 0
        self.starting = False
        """The first JOG (with the override ceiling) is still on its way: the heartbeat
        clock starts when it is answered, not before."""

    @property
    def active(self) -> bool:
        return self.request is not None

    def owned_by(self, actor: Actor) -> bool:
        held = self.actor
        return (
            held is not None
            and self.request is not None
            and (held.user, held.session_id) == (actor.user, actor.session_id)
        )

    def owned_by_user(self, user: str) -> bool:
        """Any session of ``user`` jogs (their last connection closing ends it)."""
        held = self.actor
        return held is not None and self.request is not None and held.user == user

    def begin(self, actor: Actor, request: JogRequest, command_id: int, now: float) -> None:
        with self.lock:
            self.actor = actor
            self.starting = True
            self.request = request
            self.command_id = command_id
            self.fresh = True
            self.last_heartbeat = now
            self.last_sent = now

    def heartbeat(self, actor: Actor, now: float) -> tuple[bool, bool]:
        """(jog is ours, a renewal must be queued)."""
        with self.lock:
            if not self.owned_by(actor):
                return False, False
            self.fresh = True
            self.last_heartbeat = now
            self.heartbeats += 1
            queue = not self.tick_queued
            if queue:
                self.tick_queued = True
            return True, queue

    def take_renewal(self) -> JogRequest | None:
        """In the worker: the request to send now, or None (no fresh heartbeat)."""
        with self.lock:
            self.tick_queued = False
            if self.request is None or not self.fresh:
                return None
            self.fresh = False
            self.renewals += 1
            return self.request

    def started(self, now: float) -> None:
        with self.lock:
            self.starting = False
            self.last_heartbeat = max(self.last_heartbeat, now)

    def end(self) -> tuple[Actor | None, JogRequest | None]:
        with self.lock:
            self.starting = False
            actor, request = self.actor, self.request
            self.actor = None
            self.request = None
            self.fresh = False
            return actor, request

    def view(self) -> tuple[bool, float]:
        return self.request is not None, self.last_sent


__all__ = ["JogKeeper", "JogRequest"]
