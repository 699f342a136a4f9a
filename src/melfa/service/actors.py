"""Who asks the service: an `Actor` (a signed-in person's name, `Role` and session) is
passed with every call; `SERVICE_ACTOR` is the service itself.

Its own module, below the events and the errors that both name it, so that neither has to
import the other (`melfa.service.events` re-exports all three).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from melfa.service.lab_network import Address


class Role(enum.Enum):
    """What a signed-in person may do."""

    OBSERVER = "observer"
    """Watches; may stop; never holds the lease."""
    STUDENT = "student"
    """May hold the lease when it is free."""
    INSTRUCTOR = "instructor"
    """May hold the lease and take it over from anyone."""


@dataclass(frozen=True)
class Actor:
    """Who asks: passed with every call (the web layer fills it from the login)."""

    user: str
    role: Role
    session_id: str
    address: Address | None = field(default=None, compare=False)
    """Where they ask from (the connection's peer; None: not over the network, as the ROS
    node or the service itself): the lab's networks are asked about it
    (`melfa.service.lab_network`). Never sent to other clients."""

    def __str__(self) -> str:
        return f"{self.user} ({self.role.value}, session {self.session_id})"


SERVICE_ACTOR = Actor("melfa-service", Role.INSTRUCTOR, "service")
"""The service acting on its own (closing, heartbeat loss)."""


__all__ = ["SERVICE_ACTOR", "Actor", "Role"]
