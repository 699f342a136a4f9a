"""Diagnostics while typing: the same JSON as `melfa check --format json`, for the program
(against the point names) and for the points (including RV-6S reach warnings); numbering
and stripping step numbers as `melfa fmt` does."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import Response

from melfa.kin.reach import reach_diagnostics
from melfa.lang.diagnostics import Diagnostic
from melfa.lang.numbering import renumber, strip
from melfa.lang.project import check_project
from melfa.web.convert import diagnostics_out
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import CheckIn, CheckOut, NumberIn, NumberOut, StripIn
from melfa.web.routes.workspaces import open_workspace

router = APIRouter(prefix="/api", tags=["check"], responses=ERROR_RESPONSES)


def check_texts(program: str, points: str) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """(program diagnostics, points diagnostics), as `melfa check prog.mb4 points.pos`:
    both call `melfa.lang.project.check_project`."""
    report = check_project([program], [points], reach_diagnostics)
    return list(report.programs[0]), list(report.points[0])


def check_json(program: str, points: str) -> bytes:
    """`check_texts` as the response's JSON. Built in the CPU pool, not on the event loop:
    a large program's tens of thousands of findings took the loop (and STOP with it) for
    most of a second to turn into models and JSON."""
    program_diags, point_diags = check_texts(program, points)
    out = CheckOut(program=diagnostics_out(program_diags), points=diagnostics_out(point_diags))
    return out.model_dump_json().encode()


@router.post("/check", response_model=CheckOut, summary="Check a program and its points")
async def check_program(body: CheckIn, session: SessionDep, context: ContextDep) -> Response:
    points = body.points
    if points is None and body.workspace_id is not None:
        ws = await open_workspace(context, session.user, body.workspace_id)
        points = (await context.db(context.store.workspaces.state, ws.id)).points
    data = await context.cpu(check_json, body.program, points or "")
    return Response(data, media_type="application/json")


@router.post("/number", response_model=NumberOut, summary="Number the steps (10, 20, …)")
async def number(body: NumberIn, session: SessionDep, context: ContextDep) -> NumberOut:
    result = await context.cpu(renumber, body.program, body.start, body.step)
    return NumberOut(
        ok=result.ok,
        text=result.text,
        diagnostics=diagnostics_out(list(result.diagnostics)).diagnostics,
    )


@router.post("/strip", response_model=NumberOut, summary="Remove step numbers")
async def strip_numbers(body: StripIn, session: SessionDep, context: ContextDep) -> NumberOut:
    result = await context.cpu(strip, body.program)
    return NumberOut(
        ok=result.ok,
        text=result.text,
        diagnostics=diagnostics_out(list(result.diagnostics)).diagnostics,
    )


__all__ = ["check_json", "check_texts", "router"]
