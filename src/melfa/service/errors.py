"""The service's own refusals. Controller refusals stay `melfa.robot.ControllerError`
(number + message), link failures stay `melfa.link.LinkError`: callers see whose fault it is.
"""

from __future__ import annotations

from typing import Any

from melfa.link import LinkError
from melfa.service.actors import Actor
from melfa.vocab.refusals import Asked, Refusal


class ServiceError(Exception):
    """Base of the service's own errors (our rules, not the controller's)."""


class InvalidArgument(ServiceError, ValueError):
    """A caller's argument makes no sense (a hand outside 1–8, an unknown jog axis): the
    only error the web answers with 422, naming ``field`` when there is one. Any other
    exception from the service is a bug or a failure, never "your input is invalid"."""

    def __init__(self, message: str, field: str | None = None) -> None:
        super().__init__(message)
        self.field = field


class ServiceClosed(ServiceError):
    """The service is closing or closed; nothing more is accepted."""


class Refused(ServiceError):
    """The service's policy refused a command before it was queued (`melfa.service.policy`):
    `reason` is the code every door sends, `says` and `fix` the student's words for it
    (`melfa.vocab.refusals`), `where` and `detail` what a client may point at (the line of
    a program's first error, its diagnostics). ``str()`` is the words and the fix."""

    def __init__(
        self,
        reason: Refusal,
        *,
        where: dict[str, Any] | None = None,
        detail: dict[str, Any] | None = None,
        asked: Asked | None = None,
        **facts: Any,
    ) -> None:
        self.reason = reason
        self.asked = asked
        """What the refused command asked for, where the fix depends on it (the gate's)."""
        self.says, self.fix = reason.words(asked, **facts)
        self.where = where
        self.detail = detail
        super().__init__(f"{self.says} {self.fix}")


class LeaseRequired(Refused):
    """A command that changes or moves the robot came from someone without the lease
    (`holder` holds it; None when nobody does or the caller is an observer)."""

    def __init__(
        self, holder: Actor | None, reason: Refusal = Refusal.LEASE_REQUIRED, **facts: Any
    ) -> None:
        if holder is not None:
            facts.setdefault("holder", holder.user)
        super().__init__(reason, **facts)
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
    "InvalidArgument",
    "JogBusy",
    "LeaseRequired",
    "LinkDown",
    "NoJog",
    "NotAllowed",
    "Refused",
    "ServiceClosed",
    "ServiceError",
    "ThesisMessageError",
]
