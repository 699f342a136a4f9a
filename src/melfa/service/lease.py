"""The operator lease: one USER at a time may move the robot [design.md, safety rules].

Pure logic with an injected clock. Rules:

- The lease belongs to a user, not to one session or socket: every session and connection
  of that user (two browser tabs, the desktop client, rosbridge, a script) shares it.
- A student or instructor may take a free lease (`acquire`); observers never hold it.
- With ``auto`` on, the first moving command from a student/instructor takes a free lease;
  the change is published like any other (nothing takes control silently), and the service
  gives it back when that command fails.
- Only the holder may move the robot; anyone else gets `LeaseRequired` naming the holder.
  Stop is not governed by the lease (the service lets everyone stop).
- An instructor may `take_over` from anyone, even while the arm moves.
- Motion keeps its owner: when the holder's last connection closes while the arm moves
  (a move or a program), the holder keeps the lease, shown as "disconnected, robot moving",
  until the motion ends (`motion`) or an instructor takes over. A holder that reconnects
  meanwhile simply carries on.
- An idle lease (no command, no jog, no motion for ``idle_timeout``) ends, whether it was
  taken from the IDE or over REST by a script.
- While the lab's queue is active (`queued`: someone waits or is at the arm), a free lease
  is never taken (neither by a command nor by *Take control*): only the queue gives it
  (`grant`) and takes it back (`revoke`), `melfa.service.queue_keeper`.

Every change returns a `LeaseChange` for the service to publish.
"""

from __future__ import annotations

import datetime as dt
import time
from collections.abc import Callable
from dataclasses import dataclass

from melfa.service.errors import LeaseRequired, NotAllowed
from melfa.service.events import Actor, Role, utc_now
from melfa.vocab.commands import Command
from melfa.vocab.lease import HolderState, LeaseReason
from melfa.vocab.refusals import Refusal


@dataclass(frozen=True)
class LeaseChange:
    holder: Actor | None
    previous: Actor | None
    actor: Actor | None
    reason: LeaseReason
    command: Command | None = None
    """The command that took a free lease (with `LeaseReason.TAKEN_BY_COMMAND`)."""


@dataclass(frozen=True)
class LeaseInfo:
    """Who holds the robot, since when, and how they are connected."""

    holder: Actor | None = None
    since: dt.datetime | None = None
    state: HolderState | None = None
    connections: int = 0
    idle_expires_in_s: float | None = None
    """Seconds until an idle lease ends (None: no timeout, or held on by motion)."""

    @property
    def label(self) -> str:
        """``alice — disconnected, robot moving``; ``free`` when nobody holds it."""
        if self.holder is None or self.state is None:
            return "free"
        return f"{self.holder.user} — {self.state.words}"


def same_user(a: Actor | None, b: Actor | None) -> bool:
    """Whether two actors are the same person (sessions of one user share the lease)."""
    return a is not None and b is not None and a.user == b.user


class Lease:
    """Who holds the robot.

    >>> lease = Lease()
    >>> ann = Actor("ann", Role.STUDENT, "s1")
    >>> lease.acquire(ann).reason
    <LeaseReason.ACQUIRED: 'acquired'>
    >>> lease.holds(Actor("ann", Role.STUDENT, "s2"))  # her other tab
    True
    >>> try:
    ...     lease.check(Actor("bob", Role.STUDENT, "s3"))
    ... except LeaseRequired as exc:
    ...     print(exc.holder.user)
    ann
    """

    def __init__(
        self,
        *,
        idle_timeout: float | None = None,
        auto: bool = True,
        clock: Callable[[], float] = time.monotonic,
        wall: Callable[[], dt.datetime] = utc_now,
    ) -> None:
        self.idle_timeout = idle_timeout
        self.auto = auto
        self._clock = clock
        self._wall = wall
        self.holder: Actor | None = None
        self._since: dt.datetime | None = None
        self._last_used = 0.0
        self._connections: dict[str, int] = {}
        self._motion = False
        self._orphaned = False
        self.queued = False
        """The queue gives the lease (`grant`); nobody takes a free one."""

    # ------------------------------------------------------------------ queries

    def holds(self, actor: Actor) -> bool:
        return same_user(self.holder, actor)

    def connections(self, user: str) -> int:
        return self._connections.get(user, 0)

    @property
    def orphaned(self) -> bool:
        """The holder's last connection closed while the arm moved for them."""
        return self._orphaned

    def info(self) -> LeaseInfo:
        holder = self.holder
        if holder is None:
            return LeaseInfo()
        count = self.connections(holder.user)
        if self._orphaned:
            state = HolderState.DISCONNECTED_MOVING
        elif count:
            state = HolderState.CONNECTED
        else:
            state = HolderState.NO_CONNECTION
        left = None
        if self.idle_timeout is not None and not self._motion and not self._orphaned:
            left = max(0.0, self.idle_timeout - (self._clock() - self._last_used))
        return LeaseInfo(holder, self._since, state, count, left)

    @property
    def _busy(self) -> Refusal:
        """Why someone else's command is refused while a holder has the lease."""
        return Refusal.QUEUE_ACTIVE if self.queued else Refusal.LEASE_REQUIRED

    # ------------------------------------------------------------------ taking and giving

    def check(self, actor: Actor) -> LeaseChange | None:
        """Allow a moving command from ``actor`` or raise `LeaseRequired`; with ``auto``
        a free lease is taken (the returned change is then not None)."""
        expired = self.expire()
        if self.holds(actor):
            self._last_used = self._clock()
            return expired
        if self.holder is None:
            if actor.role is Role.OBSERVER:
                raise LeaseRequired(None, Refusal.OBSERVER, user=actor.user)
            if self.queued:
                raise LeaseRequired(None, Refusal.QUEUE_ACTIVE)
            if self.auto:
                return self.acquire(actor)
            raise LeaseRequired(None, Refusal.LEASE_NOT_TAKEN)
        raise LeaseRequired(self.holder, self._busy)

    def touch(self, actor: Actor) -> None:
        """Activity by the holder (a jog heartbeat) keeps an idle timeout away."""
        if self.holds(actor):
            self._last_used = self._clock()

    def acquire(self, actor: Actor) -> LeaseChange | None:
        """Take a free lease (None if ``actor``'s user already holds it)."""
        self.expire()
        if actor.role is Role.OBSERVER:
            raise LeaseRequired(None, Refusal.OBSERVER, user=actor.user)
        if self.holds(actor):
            self._last_used = self._clock()
            return None
        if self.holder is not None:
            raise LeaseRequired(self.holder, self._busy)
        if self.queued:
            raise LeaseRequired(None, Refusal.QUEUE_ACTIVE)
        return self._set(actor, actor, LeaseReason.ACQUIRED)

    def grant(self, actor: Actor) -> LeaseChange | None:
        """The queue gives the lease to ``actor`` (their turn), from whoever held it."""
        if self.holds(actor):
            self._last_used = self._clock()
            return None
        return self._set(actor, actor, LeaseReason.TURN_STARTED)

    def revoke(self, actor: Actor) -> LeaseChange | None:
        """The queue takes the lease back from ``actor`` at the end of their turn."""
        if not self.holds(actor):
            return None
        return self._set(None, actor, LeaseReason.TURN_ENDED)

    def take_over(self, actor: Actor) -> LeaseChange | None:
        """An instructor takes the lease from whoever holds it."""
        if actor.role is not Role.INSTRUCTOR:
            raise NotAllowed(
                f"only an instructor can take over; {actor.user} is a {actor.role.value}"
            )
        if self.holds(actor):
            return None
        return self._set(actor, actor, LeaseReason.TAKEN_OVER)

    def release(
        self, actor: Actor, reason: LeaseReason = LeaseReason.RELEASED
    ) -> LeaseChange | None:
        """The holder gives the lease back (None if ``actor``'s user does not hold it)."""
        if not self.holds(actor):
            return None
        return self._set(None, actor, reason)

    # ------------------------------------------------------------------ connections

    def connected(self, actor: Actor) -> LeaseChange | None:
        """One more open connection of ``actor``'s user; a holder that comes back while
        the arm still moves for them is connected again (a change to publish)."""
        self._connections[actor.user] = self.connections(actor.user) + 1
        if self.holds(actor) and self._orphaned:
            self._orphaned = False
            self._last_used = self._clock()
            return LeaseChange(self.holder, self.holder, actor, LeaseReason.HOLDER_RECONNECTED)
        return None

    def disconnected(self, actor: Actor, *, moving: bool) -> tuple[bool, LeaseChange | None]:
        """One connection of ``actor``'s user closed. Returns whether it was their last,
        and the change: the lease ends, or, while ``moving``, stays with them marked
        "disconnected, robot moving"."""
        left = self.connections(actor.user) - 1
        if left > 0:
            self._connections[actor.user] = left
            return False, None
        self._connections.pop(actor.user, None)
        if not self.holds(actor):
            return True, None
        if moving:
            self._orphaned = True
            return True, LeaseChange(
                self.holder, self.holder, actor, LeaseReason.HOLDER_LEFT_MOVING
            )
        return True, self._set(None, actor, LeaseReason.HOLDER_DISCONNECTED)

    def motion(self, moving: bool) -> LeaseChange | None:
        """The arm started or stopped moving. Motion counts as the holder's activity; when
        it ends with the holder gone, the lease ends."""
        if moving:
            self._last_used = self._clock()
        was = self._motion
        self._motion = moving
        if was and not moving:
            self._last_used = self._clock()
        if not moving and self._orphaned:
            return self._set(None, None, LeaseReason.MOTION_ENDED)
        return None

    # ------------------------------------------------------------------ ending

    def expire(self) -> LeaseChange | None:
        """End an idle lease (with ``idle_timeout``); never while the arm moves for it."""
        if (
            self.holder is not None
            and self.idle_timeout is not None
            and not self._motion
            and not self._orphaned
            and self._clock() - self._last_used > self.idle_timeout
        ):
            return self._set(None, None, LeaseReason.IDLE_TIMEOUT)
        return None

    def clear(self, reason: LeaseReason) -> LeaseChange | None:
        if self.holder is None:
            return None
        return self._set(None, None, reason)

    def _set(self, holder: Actor | None, actor: Actor | None, reason: LeaseReason) -> LeaseChange:
        previous = self.holder
        self.holder = holder
        self._orphaned = False
        self._since = self._wall() if holder is not None else None
        self._last_used = self._clock()
        return LeaseChange(holder, previous, actor, reason)


__all__ = ["HolderState", "Lease", "LeaseChange", "LeaseInfo", "same_user"]
