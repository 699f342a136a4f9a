"""`/api/queue`: the fair queue for a shared robot (the lab's; ``?target=`` names another
shared robot when a server has more). Everyone signed in sees it; students and
instructors enter it with a text that passed the policy (checked, and pre-flight passed
when the instructor's gate is on), claim the arm when it is offered, give it back early;
instructors pause and resume it, move and skip students, extend a turn, take the arm at
once, switch attended mode and say *Arm ready*. Every change reaches every socket as a
``queue`` message (`melfa.live.messages.QueueMessage`) and is audited as ``queue.<step>``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated

from fastapi import APIRouter, Depends, Query
from pydantic import Field

from melfa.live.messages import QueueOut
from melfa.service import Actor
from melfa.service.queue_keeper import QueueKeeper
from melfa.web.context import WebContext
from melfa.web.deps import ActorDep, ContextDep, SessionDep, StaffDep, actor_of
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Input, SourceIn
from melfa.web.queues import queue_out
from melfa.web.routes.robot import operate, planned, sources
from melfa.web.targets import LAB

router = APIRouter(prefix="/api/queue", tags=["queue"], responses=ERROR_RESPONSES)

TargetQuery = Annotated[
    str, Query(max_length=40, description="The shared robot (`lab`, the default).")
]


class ClaimIn(Input):
    start: bool = Field(True, description="Load and run the queued text at once.")


class PlaceIn(Input):
    user: str = Field(max_length=100)
    position: int = Field(ge=1, le=10_000, description="1-based place in the line.")


class SkipIn(Input):
    user: str = Field(max_length=100)


class ExtendIn(Input):
    seconds: float = Field(60.0, gt=0, le=3600)


class AttendedIn(Input):
    on: bool


def keeper_of(context: WebContext, target: str) -> QueueKeeper:
    keeper = context.queues.get(target)
    if keeper is None:
        raise ApiError(404, "unknown-target", f"no shared robot named {target!r}"[:120])
    return keeper


def out(keeper: QueueKeeper) -> QueueOut:
    return queue_out(keeper.view())


async def _act(keeper: QueueKeeper, actor: Actor, name: str, call: Callable[[], None]) -> QueueOut:
    """One queue operation, logged like the robot's; its refusal in the one error shape."""

    async def run() -> None:
        call()

    await operate(actor, f"queue_{name}", run)
    return out(keeper)


@router.get("", response_model=QueueOut, summary="The queue")
async def get_queue(
    session: SessionDep, context: ContextDep, target: TargetQuery = LAB
) -> QueueOut:
    """Who is at the arm, who waits, their places and estimated starts."""
    return out(keeper_of(context, target))


@router.post("", response_model=QueueOut, summary="Join (Run on the lab robot)")
async def join(
    body: SourceIn,
    actor: ActorDep,
    session: SessionDep,
    context: ContextDep,
    target: TargetQuery = LAB,
) -> QueueOut:
    """Queue the exact program and points (from the body, else the workspace). Refused
    unless they pass the checker and, with the gate on, passed pre-flight in the cell as it
    is (409 ``simulation-required``, ``cell-changed``). Joining again replaces the text and
    keeps the place."""
    keeper = keeper_of(context, target)
    program, points, origin = await sources(context, session, body)
    assert program is not None and points is not None
    workspace_id = origin.workspace_id
    plan = await planned(context, program, points)
    return await _act(
        keeper, actor, "join", lambda: keeper.join(actor, plan, program, points, workspace_id)
    )


@router.delete("/me", response_model=QueueOut, summary="Leave")
async def leave(actor: ActorDep, context: ContextDep, target: TargetQuery = LAB) -> QueueOut:
    keeper = keeper_of(context, target)
    return await _act(keeper, actor, "leave", lambda: keeper.leave(actor))


@router.post("/claim", response_model=QueueOut, summary="Claim the offered arm")
async def claim(
    body: ClaimIn, actor: ActorDep, context: ContextDep, target: TargetQuery = LAB
) -> QueueOut:
    """The lease is yours for the turn; with ``start`` the queued text loads and runs
    (watch the socket's ``progress`` and ``result`` messages). 409 ``not-your-turn``."""
    keeper = keeper_of(context, target)
    return await _act(keeper, actor, "claim", lambda: keeper.claim(actor, start=body.start))


@router.post("/done", response_model=QueueOut, summary="Give the arm back early")
async def done(actor: ActorDep, context: ContextDep, target: TargetQuery = LAB) -> QueueOut:
    keeper = keeper_of(context, target)
    return await _act(keeper, actor, "done", lambda: keeper.finish(actor))


# ---------------------------------------------------------------------- the instructor


@dataclass(frozen=True)
class _Staff:
    """A member of staff acting on one shared robot's queue."""

    context: WebContext
    target: str
    by: Actor

    async def act(self, name: str, call: Callable[[QueueKeeper, Actor], None]) -> QueueOut:
        keeper = keeper_of(self.context, self.target)
        return await _act(keeper, self.by, name, lambda: call(keeper, self.by))


async def _staff(session: StaffDep, context: ContextDep, target: TargetQuery = LAB) -> _Staff:
    """Async like every dependency: FastAPI runs a plain ``def`` in its shared pool."""
    return _Staff(context, target, actor_of(session))


StaffQueue = Annotated[_Staff, Depends(_staff)]


@router.post("/pause", response_model=QueueOut, summary="Pause (instructors)")
async def pause(staff: StaffQueue) -> QueueOut:
    return await staff.act("pause", lambda q, by: q.pause(by))


@router.post("/resume", response_model=QueueOut, summary="Resume (instructors)")
async def resume(staff: StaffQueue) -> QueueOut:
    """A turn kept while you held the arm continues with its time left."""
    return await staff.act("resume", lambda q, by: q.resume(by))


@router.post("/move", response_model=QueueOut, summary="Move a student (instructors)")
async def move(body: PlaceIn, staff: StaffQueue) -> QueueOut:
    return await staff.act("move", lambda q, by: q.move(body.user, body.position, by))


@router.post("/skip", response_model=QueueOut, summary="Skip a student (instructors)")
async def skip(body: SkipIn, staff: StaffQueue) -> QueueOut:
    """Out of the queue; at the arm, the turn ends and a running program is stopped."""
    return await staff.act("skip", lambda q, by: q.skip(body.user, by))


@router.post("/extend", response_model=QueueOut, summary="Extend the turn (instructors)")
async def extend(body: ExtendIn, staff: StaffQueue) -> QueueOut:
    return await staff.act("extend", lambda q, by: q.extend(body.seconds, by))


@router.post("/take", response_model=QueueOut, summary="Take the arm at once (instructors)")
async def take(staff: StaffQueue) -> QueueOut:
    """The lease is yours and the queue pauses; the turn at the arm keeps its time left."""
    return await staff.act("take", lambda q, by: q.take(by))


@router.put("/attended", response_model=QueueOut, summary="Attended mode (instructors)")
async def attended(body: AttendedIn, staff: StaffQueue) -> QueueOut:
    """On: each run on the arm waits for your *Arm ready*."""
    return await staff.act("attended", lambda q, by: q.set_attended(body.on, by))


@router.post("/ready", response_model=QueueOut, summary="Arm ready (instructors)")
async def ready(staff: StaffQueue) -> QueueOut:
    """Attended mode: the waiting run goes (or the next run will, when none waits)."""
    return await staff.act("ready", lambda q, by: q.arm_ready(by))


__all__ = ["router"]
