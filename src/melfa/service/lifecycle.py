"""The service's own life: new → running → closing → closed, as data (h11's ``_state.py``,
Starlette's ``WebSocketState``). A wrong move raises at once, naming both states.

>>> life = Life()
>>> life.state
<Lifecycle.NEW: 'new'>
>>> life.move(Lifecycle.RUNNING)
>>> life.move(Lifecycle.NEW)
Traceback (most recent call last):
...
melfa.service.lifecycle.LifecycleError: the service cannot go from running to new
"""

from __future__ import annotations

import enum

from melfa.service.errors import ServiceClosed, ServiceError


class Lifecycle(enum.Enum):
    NEW = "new"
    """Made, not started: no worker, no link."""
    RUNNING = "running"
    """The worker owns the link; commands are accepted."""
    CLOSING = "closing"
    """`RobotService.close` is under way: only STOP is still accepted."""
    CLOSED = "closed"


TRANSITIONS: dict[Lifecycle, frozenset[Lifecycle]] = {
    Lifecycle.NEW: frozenset({Lifecycle.RUNNING, Lifecycle.CLOSED}),
    Lifecycle.RUNNING: frozenset({Lifecycle.CLOSING}),
    Lifecycle.CLOSING: frozenset({Lifecycle.CLOSED}),
    Lifecycle.CLOSED: frozenset(),
}
"""Every move the service may make; anything else is a bug."""


class LifecycleError(ServiceError):
    """A move the transition table does not allow (a bug in the caller, not the user)."""


class Life:
    """The current `Lifecycle` state and its checked moves."""

    def __init__(self) -> None:
        self.state = Lifecycle.NEW

    def move(self, to: Lifecycle) -> None:
        if to not in TRANSITIONS[self.state]:
            raise LifecycleError(f"the service cannot go from {self.state.value} to {to.value}")
        self.state = to

    @property
    def running(self) -> bool:
        return self.state is Lifecycle.RUNNING

    def check_open(self) -> None:
        """Commands are accepted only while running."""
        if self.state is Lifecycle.NEW:
            raise ServiceError("the service has not been started (await service.start())")
        if self.state is not Lifecycle.RUNNING:
            raise ServiceClosed("the robot service is closed")


__all__ = ["TRANSITIONS", "Life", "Lifecycle", "LifecycleError"]
