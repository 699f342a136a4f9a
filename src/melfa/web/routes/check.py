"""Diagnostics while typing: the same JSON as `melfa check --format json`, for the program
(against the point names) and for the points (including RV-6S reach warnings); numbering
and stripping step numbers as `melfa fmt` does."""

from __future__ import annotations

from fastapi import APIRouter

from melfa.lang.check import check
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.numbering import renumber, strip
from melfa.lang.points import parse_points
from melfa.web.convert import diagnostics_out
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import CheckIn, CheckOut, NumberIn, NumberOut, StripIn
from melfa.web.routes.workspaces import open_workspace

router = APIRouter(prefix="/api", tags=["check"], responses=ERROR_RESPONSES)

_ORDER = {Severity.ERROR: 0, Severity.WARNING: 1, Severity.INFO: 2}


def _by_position(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return sorted(diagnostics, key=lambda d: (d.line, d.column, _ORDER[d.severity]))


def check_texts(program: str, points: str) -> tuple[list[Diagnostic], list[Diagnostic]]:
    """(program diagnostics, points diagnostics), as `melfa check prog.mb4 points.pos`."""
    parsed = parse_points(points)
    point_diags = list(parsed.diagnostics)
    if parsed.points:
        from melfa.kin.reach import reach_diagnostics

        point_diags.extend(reach_diagnostics(parsed.points, points))
    program_diags = check(program, parsed.names)
    return _by_position(program_diags), _by_position(point_diags)


@router.post("/check", response_model=CheckOut, summary="Check a program and its points")
async def check_program(body: CheckIn, session: SessionDep, context: ContextDep) -> CheckOut:
    points = body.points
    if points is None and body.workspace_id is not None:
        ws = await open_workspace(context, session.user, body.workspace_id)
        points = (await context.db(context.store.workspaces.state, ws.id)).points
    program_diags, point_diags = await context.db(check_texts, body.program, points or "")
    return CheckOut(program=diagnostics_out(program_diags), points=diagnostics_out(point_diags))


@router.post("/number", response_model=NumberOut, summary="Number the steps (10, 20, …)")
async def number(body: NumberIn, session: SessionDep, context: ContextDep) -> NumberOut:
    result = await context.db(renumber, body.program, body.start, body.step)
    return NumberOut(
        ok=result.ok,
        text=result.text,
        diagnostics=diagnostics_out(list(result.diagnostics)).diagnostics,
    )


@router.post("/strip", response_model=NumberOut, summary="Remove step numbers")
async def strip_numbers(body: StripIn, session: SessionDep, context: ContextDep) -> NumberOut:
    result = await context.db(strip, body.program)
    return NumberOut(
        ok=result.ok,
        text=result.text,
        diagnostics=diagnostics_out(list(result.diagnostics)).diagnostics,
    )


__all__ = ["check_texts", "router"]
