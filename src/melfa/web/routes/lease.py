"""The operator lease: who may move the robot. Anyone signed in sees it (holder, since
when, connection state); students and instructors take a free one for all their sessions;
instructors (and admins) take over from anyone (`melfa.service.lease`)."""

from __future__ import annotations

from fastapi import APIRouter

from melfa.service import Actor
from melfa.service.lease import same_user
from melfa.web.context import WebContext
from melfa.web.convert import actor_out
from melfa.web.deps import ActorDep, ContextDep, StaffDep, actor_of
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import LeaseOut
from melfa.web.routes.robot import operate

router = APIRouter(prefix="/api/lease", tags=["lease"], responses=ERROR_RESPONSES)


def lease_out(context: WebContext, actor: Actor) -> LeaseOut:
    info = context.service.lease_info()
    return LeaseOut(
        holder=actor_out(info.holder),
        you=same_user(info.holder, actor),
        since=info.since,
        state=info.state.value if info.state is not None else None,
        label=info.label,
        connections=info.connections,
        idle_expires_in_s=info.idle_expires_in_s,
    )


@router.get("", response_model=LeaseOut, summary="Who holds the robot")
async def get_lease(actor: ActorDep, context: ContextDep) -> LeaseOut:
    return lease_out(context, actor)


@router.post("", response_model=LeaseOut, summary="Take the free lease")
async def take_lease(actor: ActorDep, context: ContextDep) -> LeaseOut:
    """423 ``lease-required`` naming the holder when someone else has it."""

    async def acquire() -> None:
        context.service.acquire_lease(actor)

    await operate(actor, "lease_acquire", acquire)
    return lease_out(context, actor)


@router.delete("", response_model=LeaseOut, summary="Give the lease back")
async def release_lease(actor: ActorDep, context: ContextDep) -> LeaseOut:
    context.service.release_lease(actor)
    return lease_out(context, actor)


@router.post("/takeover", response_model=LeaseOut, summary="Take over (instructors)")
async def take_over(session: StaffDep, context: ContextDep) -> LeaseOut:
    """The holder's jog ends; everyone's WebSocket gets a ``lease`` message."""
    actor = actor_of(session)

    async def take() -> None:
        context.service.take_over(actor)

    await operate(actor, "lease_takeover", take)
    return lease_out(context, actor)


__all__ = ["lease_out", "router"]
