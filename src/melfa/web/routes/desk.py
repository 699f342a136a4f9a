"""The instructor's desk: the lab robot's settings staff switch live from the IDE.

The simulation gate (`melfa.service.policy.Gate`) was a start-up flag; here staff turn it
on and off while the server runs, and every door (REST, WebSocket, rosbridge, the thesis's
messages) obeys at once because they all pass the one policy. Each switch is audited."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response
from pydantic import BaseModel, Field

from melfa.store import AuditEvent
from melfa.vocab.desk import DeskAction
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Input
from melfa.web.routes.pages import staff_page

router = APIRouter(prefix="/api/desk", tags=["desk"], responses=ERROR_RESPONSES)
pages = APIRouter(include_in_schema=False)


class DeskOut(BaseModel):
    require_simulation: bool = Field(
        description="The lab robot loads and runs only texts that passed pre-flight (the gate)."
    )


class GateIn(Input):
    require_simulation: bool


def _desk(context: WebContext) -> DeskOut:
    return DeskOut(require_simulation=context.service.policy.simulation_required)


@router.get("", response_model=DeskOut, summary="The lab robot's settings (staff)")
async def desk(session: StaffDep, context: ContextDep) -> DeskOut:
    return _desk(context)


@router.put("/gate", response_model=DeskOut, summary="Turn the simulation gate on or off")
async def set_gate(body: GateIn, session: StaffDep, context: ContextDep) -> DeskOut:
    gate = context.service.policy.gate
    if gate is None:
        raise ApiError(409, "refused", "this robot has no simulation gate")
    gate.required = body.require_simulation
    await context.store.audit.record_async(
        AuditEvent(
            action=DeskAction.GATE.value,
            actor=session.user.username,
            role=session.user.role.value,
            details={"state": "on" if body.require_simulation else "off"},
        )
    )
    return _desk(context)


@pages.get("/desk", response_model=None)
async def desk_page(request: Request) -> Response:
    """The instructor's desk (static/desk.html): staff only."""
    return await staff_page(
        request, "desk.html", "<p>Only instructors and admins use the instructor's desk.</p>"
    )


__all__ = ["pages", "router"]
