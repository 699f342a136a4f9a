"""The operator lease: one session at a time may move the robot [design.md, safety rules].

Pure logic with an injected clock. Rules:

- A student or instructor may take a free lease (`acquire`); observers never hold it.
- With ``auto`` on, the first moving command from a student/instructor takes a free lease.
- Only the holder's session may move the robot; anyone else gets `LeaseRequired` naming
  the holder. Stop is not governed by the lease (the service lets everyone stop).
- An instructor may `take_over` from anyone.
- The lease ends when its holder releases it, disconnects, or (with ``idle_timeout``) has
  sent no command for that long.

Every change returns a `LeaseChange` for the service to publish.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from melfa.service.errors import LeaseRequired, NotAllowed
from melfa.service.events import Actor, Role


@dataclass(frozen=True)
class LeaseChange:
    holder: Actor | None
    previous: Actor | None
    actor: Actor | None
    reason: str


def _same(a: Actor | None, b: Actor | None) -> bool:
    return a is not None and b is not None and (a.user, a.session_id) == (b.user, b.session_id)


class Lease:
    """Who holds the robot.

    >>> lease = Lease()
    >>> ann = Actor("ann", Role.STUDENT, "s1")
    >>> lease.acquire(ann).reason
    'acquired'
    >>> try:
    ...     lease.check(Actor("bob", Role.STUDENT, "s2"))
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
    ) -> None:
        self.idle_timeout = idle_timeout
        self.auto = auto
        self._clock = clock
        self.holder: Actor | None = None
        self._last_used = 0.0

    def holds(self, actor: Actor) -> bool:
        return _same(self.holder, actor)

    def check(self, actor: Actor) -> LeaseChange | None:
        """Allow a moving command from ``actor`` or raise `LeaseRequired`; with ``auto``
        a free lease is taken (the returned change is then not None)."""
        expired = self.expire()
        if self.holds(actor):
            self._last_used = self._clock()
            return expired
        if self.holder is None:
            if actor.role is Role.OBSERVER:
                raise LeaseRequired(f"{actor.user} is an observer and cannot move the robot", None)
            if self.auto:
                return self.acquire(actor)
            raise LeaseRequired("nobody holds the robot: take the operator lease first", None)
        raise LeaseRequired(
            f"{self.holder.user} holds the robot; ask them to release it, "
            "or an instructor to take over",
            self.holder,
        )

    def acquire(self, actor: Actor) -> LeaseChange | None:
        """Take a free lease (None if ``actor`` already holds it)."""
        self.expire()
        if actor.role is Role.OBSERVER:
            raise NotAllowed(f"{actor.user} is an observer and cannot hold the robot")
        if self.holds(actor):
            self._last_used = self._clock()
            return None
        if self.holder is not None:
            raise LeaseRequired(
                f"{self.holder.user} holds the robot; an instructor can take over",
                self.holder,
            )
        return self._set(actor, actor, "acquired")

    def take_over(self, actor: Actor) -> LeaseChange | None:
        """An instructor takes the lease from whoever holds it."""
        if actor.role is not Role.INSTRUCTOR:
            raise NotAllowed(
                f"only an instructor can take over; {actor.user} is a {actor.role.value}"
            )
        if self.holds(actor):
            return None
        return self._set(actor, actor, "taken over")

    def release(self, actor: Actor) -> LeaseChange | None:
        """The holder gives the lease back (None if ``actor`` does not hold it)."""
        if not self.holds(actor):
            return None
        return self._set(None, actor, "released")

    def disconnect(self, actor: Actor) -> LeaseChange | None:
        """``actor``'s session went away."""
        if not self.holds(actor):
            return None
        return self._set(None, actor, "holder disconnected")

    def expire(self) -> LeaseChange | None:
        """End an idle lease (with ``idle_timeout``)."""
        if (
            self.holder is not None
            and self.idle_timeout is not None
            and self._clock() - self._last_used > self.idle_timeout
        ):
            return self._set(None, None, "idle timeout")
        return None

    def clear(self, reason: str) -> LeaseChange | None:
        if self.holder is None:
            return None
        return self._set(None, None, reason)

    def _set(self, holder: Actor | None, actor: Actor | None, reason: str) -> LeaseChange:
        previous = self.holder
        self.holder = holder
        self._last_used = self._clock()
        return LeaseChange(holder, previous, actor, reason)


__all__ = ["Lease", "LeaseChange"]
