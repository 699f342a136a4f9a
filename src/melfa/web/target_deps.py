"""The ``target`` query parameter of robot routes, resolved once: the `Drive` a route uses
is the chosen robot's service and the caller as that robot's operator."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated

from fastapi import Depends, Query

from melfa.service import Actor, RobotService
from melfa.web.deps import ActorDep, ContextDep, SessionDep
from melfa.web.errors import ApiError
from melfa.web.targets import LAB, MINE, Target, Targets, UnknownTarget

TARGET_HELP = (
    f"Which robot: `{LAB}` (the lab's, shared and leased; the default) "
    f"or `{MINE}` (your own simulator)."
)


@dataclass(frozen=True)
class Drive:
    """What a robot route drives (``target``) and as whom (``actor``)."""

    target: Target
    actor: Actor

    @property
    def service(self) -> RobotService:
        return self.target.service


async def find_target(targets: Targets, user: str, target: str) -> Target:
    """``target`` of ``user``, or 404 ``unknown-target``."""
    try:
        return await targets.get(user, target)
    except UnknownTarget:
        raise ApiError(
            404,
            "unknown-target",
            f"no robot {target!r}: use {LAB!r} (the lab's) or {MINE!r} (your simulator)",
            where={"field": "target"},
        ) from None


async def get_drive(
    session: SessionDep,
    actor: ActorDep,
    context: ContextDep,
    target: Annotated[str, Query(description=TARGET_HELP)] = LAB,
) -> Drive:
    chosen = await find_target(context.targets, session.user.username, target)
    return Drive(chosen, chosen.actor(actor))


DriveDep = Annotated[Drive, Depends(get_drive)]

__all__ = ["TARGET_HELP", "Drive", "DriveDep", "find_target", "get_drive"]
