"""`/api/preflight`: a program's simulated run checked before the real arm moves (cycle time,
joint margins, unreachable targets, singularities, the tool below the table or inside a
box of the lab's cell), the cell model instructors edit, and the instructor's gate."""

from __future__ import annotations

import asyncio
from typing import Any

from fastapi import APIRouter
from pydantic import BaseModel, Field

from melfa.sim.debug.cell import Cell, CellError
from melfa.sim.debug.cell_templates import template
from melfa.sim.debug.engine import DebugError
from melfa.sim.debug.preflight import preflight
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, SessionDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Input, SourceIn
from melfa.web.preflight_passes import keep_pass
from melfa.web.routes.robot import checked_program, planned, sources

router = APIRouter(prefix="/api", tags=["preflight"], responses=ERROR_RESPONSES)


class PreflightIn(SourceIn):
    inputs: dict[int, int] = Field(
        default_factory=dict, description="`M_IN(n)` values the run starts with."
    )


class PreflightOut(BaseModel):
    """The report (`ok`, `finished`, `cycle_time`, `duration`, `joints` margins, `findings`
    `{kind, severity, message, line, segment: {move, start, end}}`, `path` samples
    `[t, x, y, z, move, line]`, `error`), and whether it opens the gate."""

    report: dict[str, Any]
    passed: bool = Field(description="No pre-flight error: the lab robot may run this text.")
    cell: dict[str, Any]


class CellIn(Input):
    """The cell's JSON (docs/simulator.md); `melfa.sim.debug.cell.Cell.from_json` checks it
    and says what is wrong in the instructor's words."""

    floor_z: float | None = Field(0.0, description="The table plane (mm); null: no check.")
    boxes: list[dict[str, Any]] = Field(
        default_factory=list, description="`{name, min: [x,y,z], max: [x,y,z]}` in mm."
    )
    fixtures: list[dict[str, Any]] = Field(
        default_factory=list,
        description="`{name, shape: box|cylinder, size|diameter+height, position, rz}`.",
    )
    parts: list[dict[str, Any]] = Field(
        default_factory=list, description="Solids the program moves, as fixtures."
    )
    gripper: dict[str, Any] = Field(
        default_factory=dict, description="`{hand, grip, tolerance, length, radius}`."
    )
    sensors: list[dict[str, Any]] = Field(
        default_factory=list, description="`{name, input, min, max}`: M_IN(input) = part in."
    )
    conveyors: list[dict[str, Any]] = Field(
        default_factory=list,
        description="`{name, output, size, position, velocity: [vx, vy]}`: runs on M_OUT.",
    )


class PreflightSettingsOut(BaseModel):
    cell: dict[str, Any]
    require_simulation: bool = Field(
        description="The lab robot runs only texts that passed pre-flight (the gate)."
    )


def settings_out(context: WebContext) -> PreflightSettingsOut:
    return PreflightSettingsOut(
        cell=context.preflight.cell.to_json(),
        require_simulation=context.service.policy.simulation_required,
    )


@router.post("/preflight", response_model=PreflightOut, summary="Pre-flight a program")
async def run_preflight(
    body: PreflightIn, session: SessionDep, context: ContextDep
) -> PreflightOut:
    """Runs the program (from the body, else the workspace) at instant speed on a fresh
    simulated arm in the lab's cell; nothing moves. A report without errors lets the lab
    robot run the same text when the gate is on."""
    program, points, _ = await sources(context, session, body)
    assert program is not None and points is not None
    plan = await planned(context, program, points)
    checked_program(plan, body.check)
    state = context.preflight
    cell = state.cell
    try:
        report = await asyncio.to_thread(
            preflight, program, points, cell=cell, inputs=tuple(body.inputs.items())
        )
    except DebugError as exc:
        raise ApiError(422, "debug-refused", str(exc)) from None
    if report.ok:
        # In the cell it ran in: an edit made meanwhile makes the pass not count. Kept in
        # the store, read by the gate and by the comparison of a later real run.
        await keep_pass(context, session.user.username, plan, report, cell.digest())
    return PreflightOut(report=report.to_json(), passed=report.ok, cell=cell.to_json())


@router.get("/preflight", response_model=PreflightSettingsOut, summary="Cell and gate")
async def get_settings(session: SessionDep, context: ContextDep) -> PreflightSettingsOut:
    return settings_out(context)


@router.get("/preflight/templates/{name}", response_model=dict[str, Any], summary="A template cell")
async def get_template(name: str, session: StaffDep) -> dict[str, Any]:
    """Instructors and admins: a cell to start from (``thesis-bench``: the thesis's bench
    and blocks, for examples/pyramid.MB4)."""
    try:
        return template(name).to_json()
    except CellError as exc:
        raise ApiError(404, "not-found", str(exc)) from None


@router.put("/preflight/cell", response_model=PreflightSettingsOut, summary="Edit the cell")
async def put_cell(body: CellIn, session: StaffDep, context: ContextDep) -> PreflightSettingsOut:
    """Instructors and admins: the table, fixtures, parts, gripper, sensors and conveyors
    (mm, base frame; docs/simulator.md)."""
    try:
        cell = Cell.from_json(body.model_dump())
    except CellError as exc:
        raise ApiError(422, "invalid-cell", str(exc), where={"field": "cell"}) from None
    await asyncio.to_thread(context.preflight.save_cell, cell, session.user)
    for queue in context.queues.values():  # a queued student whose pass no longer counts
        queue.gate_changed()  # is told now, not when their turn is refused
    return settings_out(context)


__all__ = ["router"]
