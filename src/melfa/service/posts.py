"""What the worker thread (and the jobs it runs) hands to the event loop: one frozen class
per kind of news, handled by the service in one ``match`` (`RobotService._on_post`).

The worker never touches the service's state: it posts, and the loop applies the post.
"""

from __future__ import annotations

from dataclasses import dataclass

from melfa.service.events import Actor, Event, LinkStatus
from melfa.service.polling import PollResult
from melfa.vocab.activity import Motion
from melfa.vocab.commands import Command


@dataclass(frozen=True)
class Polled:
    """A poll read the robot."""

    result: PollResult


@dataclass(frozen=True)
class BusyChanged:
    """A long job (an upload) holds the line, or let it go (None)."""

    busy: str | None


@dataclass(frozen=True)
class LinkChanged:
    """The link's status changed."""

    status: LinkStatus
    detail: str = ""


@dataclass(frozen=True)
class Publish:
    """An event made in the worker (upload progress) for the bus."""

    event: Event


@dataclass(frozen=True)
class ServoTurnedOn:
    """The servo rule switched the servo on before ``command`` (`melfa.service.servo`)."""

    actor: Actor
    command: Command


@dataclass(frozen=True)
class JogRefused:
    """A JOG renewal failed: the jog ends with the controller's refusal."""

    error: BaseException


@dataclass(frozen=True, eq=False)
class MotionSent:
    """The controller answered the command of ``motion`` (posted from the job itself, so
    it comes before the next poll's news)."""

    motion: Motion


Post = Polled | BusyChanged | LinkChanged | Publish | ServoTurnedOn | JogRefused | MotionSent


__all__ = [
    "BusyChanged",
    "JogRefused",
    "LinkChanged",
    "MotionSent",
    "Polled",
    "Post",
    "Publish",
    "ServoTurnedOn",
]
