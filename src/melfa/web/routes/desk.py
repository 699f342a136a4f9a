"""The instructor's desk: the lab robot's settings staff switch live from the IDE.

The simulation gate (`melfa.service.policy.Gate`) was a start-up flag; here staff turn it
on and off while the server runs, and every door (REST, WebSocket, rosbridge, the thesis's
messages) obeys at once because they all pass the one policy. *Stop and hold* stops the
robot and holds it (`Policy.hold`): nothing a student sends starts, and each refusal names
who holds it, until a member of staff releases it. *Where students drive from* sets the lab's
networks (`melfa.service.lab_network`, ``melfa serve --lab-network``): from elsewhere a
student's commands to the lab robot are refused. Each switch is audited. The gate and the
networks are saved before they apply and kept across a restart, on the floor of the
start-up options (`melfa.web.desk_settings`, `melfa.service.live_settings`); the desk says
where each came from. A hold is not kept: a restart stops whatever ran anyway."""

from __future__ import annotations

import datetime as dt
from typing import TypeVar

from fastapi import APIRouter, Request
from fastapi.responses import Response
from pydantic import BaseModel, Field

from melfa.service.lab_network import UNKNOWN_PEER, NetworkError, parse_networks
from melfa.service.live_settings import Origin
from melfa.store import Session
from melfa.vocab.desk import DESK_WORDS, DeskAction, SettingSource
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, StaffDep, actor_of, peer_of
from melfa.web.desk_audit import audit_desk
from melfa.web.desk_settings import GATE, LAB_NETWORKS
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Input, ShortText
from melfa.web.routes.pages import staff_page

router = APIRouter(prefix="/api/desk", tags=["desk"], responses=ERROR_RESPONSES)
pages = APIRouter(include_in_schema=False)

_Setting = TypeVar("_Setting")


class SettingFrom(BaseModel):
    """Where a setting in force came from (`melfa.service.live_settings`)."""

    source: SettingSource = Field(
        description="default (nobody set it), command-line (the server's start-up option) "
        "or desk (staff chose it; saved, a restart keeps it within the start-up option)."
    )
    by: str | None = Field(description="Who chose it on the desk (null: not the desk).")
    at: dt.datetime | None = Field(description="When they chose it (null: not the desk).")
    command_line: str | None = Field(
        description="The server's start-up option for it, as written "
        "(--require-simulation; --lab-network 192.168.10.0/24); null: started without."
    )
    until_restart: bool = Field(
        description="The desk's choice is looser than the start-up option: a restart "
        "goes back to the option."
    )
    cut_from: list[str] = Field(
        description="The desk's networks when they lie only partly inside the start-up "
        "option: only that part holds after a start (what `lab_networks` shows; with "
        "until_restart, at the next one). Empty otherwise."
    )


class DeskOut(BaseModel):
    require_simulation: bool = Field(
        description="The lab robot loads and runs only texts that passed pre-flight (the gate)."
    )
    require_simulation_from: SettingFrom
    held_by: str | None = Field(
        description="Who of the staff stopped the lab robot and holds it (null: nobody)."
    )
    lab_networks: list[str] = Field(
        description="Where students may drive the lab robot from, as CIDR networks "
        "(192.168.10.0/24); empty: anywhere."
    )
    lab_networks_from: SettingFrom
    your_address: str | None = Field(
        description="The address this request came from (null: not known)."
    )


class GateIn(Input):
    require_simulation: bool


class LabNetworkIn(Input):
    networks: list[ShortText] = Field(
        max_length=64,
        description="CIDR networks (192.168.10.0/24; one address is its /32); empty: anywhere.",
    )


def _switchable(setting: _Setting | None, missing: str) -> _Setting:
    """The setting a switch changes, or 409 saying this robot has none (a robot built
    without a gate or a lab-network setting)."""
    if setting is None:
        raise ApiError(409, "refused", missing)
    return setting


def _from(origin: Origin, command_line: str | None) -> SettingFrom:
    return SettingFrom(
        source=origin.source,
        by=origin.by,
        at=origin.at,
        command_line=command_line,
        until_restart=origin.until_restart,
        cut_from=[str(n) for n in origin.cut_from],
    )


def _desk(context: WebContext, request: Request) -> DeskOut:
    policy = context.service.policy
    settings = context.desk
    options = settings.options
    return DeskOut(
        require_simulation=policy.simulation_required,
        require_simulation_from=_from(settings.gate_origin, options.written(GATE)),
        held_by=policy.held_by,
        lab_networks=policy.lab.written() if policy.lab is not None else [],
        lab_networks_from=_from(settings.networks_origin, options.written(LAB_NETWORKS)),
        your_address=None if (peer := peer_of(request)) == UNKNOWN_PEER else str(peer),
    )


async def _switched(
    context: WebContext, request: Request, session: Session, action: DeskAction, **details: object
) -> DeskOut:
    """Every switch ends alike: audited in the staff member's name, then the desk as it now is."""
    await audit_desk(context, session, action, **details)
    return _desk(context, request)


@router.get("", response_model=DeskOut, summary="The lab robot's settings (staff)")
async def desk(request: Request, session: StaffDep, context: ContextDep) -> DeskOut:
    return _desk(context, request)


@router.put("/gate", response_model=DeskOut, summary="Turn the simulation gate on or off")
async def set_gate(
    request: Request, body: GateIn, session: StaffDep, context: ContextDep
) -> DeskOut:
    """Saved, then at once for every door; a restart keeps it (on the floor of
    ``--require-simulation``: a server started with it starts with the gate on)."""
    _switchable(context.service.policy.gate, "this robot has no simulation gate")
    await context.desk.set_gate(body.require_simulation, session.user.username)
    state = "on" if body.require_simulation else "off"
    return await _switched(context, request, session, DeskAction.GATE, state=state)


@router.post("/hold", response_model=DeskOut, summary="Stop the lab robot and hold it")
async def hold(request: Request, session: StaffDep, context: ContextDep) -> DeskOut:
    """Held first, then stopped: nothing queued after the STOP can start."""
    context.service.policy.hold(session.user.username)
    await context.service.stop(actor_of(session))
    return await _switched(context, request, session, DeskAction.HOLD)


@router.delete("/hold", response_model=DeskOut, summary="Release the lab robot")
async def release(request: Request, session: StaffDep, context: ContextDep) -> DeskOut:
    context.service.policy.hold(None)
    return await _switched(context, request, session, DeskAction.RELEASE)


@router.put("/lab-network", response_model=DeskOut, summary="Set where students may drive from")
async def set_lab_network(
    request: Request, body: LabNetworkIn, session: StaffDep, context: ContextDep
) -> DeskOut:
    """Saved, then at once for every door; 422 naming the entry that is not a network. A
    restart keeps what lies inside ``--lab-network`` when the server starts with it."""
    lab = _switchable(context.service.policy.lab, "this robot has no lab network setting")
    try:
        networks = parse_networks(body.networks)
    except NetworkError as exc:
        raise ApiError(422, "invalid-request", str(exc), where={"field": "networks"}) from None
    await context.desk.set_networks(networks, session.user.username)
    written = ", ".join(lab.written()) or DESK_WORDS["anywhere"]
    return await _switched(context, request, session, DeskAction.LAB_NETWORK, networks=written)


@pages.get("/desk", response_model=None)
async def desk_page(request: Request) -> Response:
    """The instructor's desk (static/desk.html): staff only."""
    return await staff_page(
        request, "desk.html", "<p>Only instructors and admins use the instructor's desk.</p>"
    )


__all__ = ["pages", "router"]
