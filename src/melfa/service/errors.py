"""The service's own refusals. Controller refusals stay `melfa.robot.ControllerError`
(number + message), link failures stay `melfa.link.LinkError`: callers see whose fault it is.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from melfa.link import LinkError

if TYPE_CHECKING:
    from melfa.service.events import Actor


class ServiceError(Exception):
    """Base of the service's own errors (our rules, not the controller's)."""


class ServiceClosed(ServiceError):
    """The service is closing or closed; nothing more is accepted."""


class LeaseRequired(ServiceError):
    """A command that changes or moves the robot came from someone without the lease."""

    def __init__(self, message: str, holder: Actor | None = None) -> None:
        super().__init__(message)
        self.holder = holder


class NotAllowed(ServiceError):
    """The caller's role may not do this (an observer taking the lease, a student taking
    over)."""


class Cancelled(ServiceError):
    """A queued command was dropped before it reached the controller (stop, close)."""


class JogBusy(ServiceError):
    """A step jog was refused because the previous step is still queued or moving: the
    service never builds a backlog of moves."""


class NoJog(ServiceError):
    """A heartbeat or release for a session that has no jog running."""


class LinkDown(LinkError):
    """The robot link is down and the service is reconnecting; the command was not sent."""


class ThesisMessageError(ServiceError):
    """A thesis control message that makes no sense in the adapter's current state."""


__all__ = [
    "Cancelled",
    "JogBusy",
    "LeaseRequired",
    "LinkDown",
    "NoJog",
    "NotAllowed",
    "ServiceClosed",
    "ServiceError",
    "ThesisMessageError",
]
