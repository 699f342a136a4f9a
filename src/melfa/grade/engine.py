"""Grading: one submission against one assignment (and a student's variant) → a `Report`.

The one engine behind `melfa grade`, the IDE's *Check my solution* and *Submit*. The
program is checked (`melfa.lang.project.check_project`) and read as a tree once; it runs on
the simulated RV-6S in the assignment's cell (`melfa.sim.debug.preflight`) once for each
set of inputs its checks ask for; each check reads the run or the tree (`checks`). A
program with errors is never run: every check that needs a run fails with the checker's
first error and its line. Never raises for anything in the submission.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from melfa.grade import checks as C  # noqa: N812
from melfa.grade.assignment import Assignment
from melfa.grade.model import (
    Avoids,
    Check,
    CheckKind,
    CycleTime,
    FinalPose,
    Hand,
    Io,
    NoCollision,
    NoErrors,
    PartAt,
    Uses,
    Visits,
)
from melfa.grade.report import NOT_RUN, CheckResult, Report
from melfa.grade.variants import Variant, shifted
from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Diagnostic
from melfa.lang.lexer import tokenize
from melfa.lang.parser import parse_tokens
from melfa.lang.points import PointDef, PointKind
from melfa.lang.points_read import parse_points
from melfa.lang.points_write import format_points
from melfa.lang.project import check_project
from melfa.sim.debug.cell import Cell
from melfa.sim.debug.engine import DebugError
from melfa.sim.debug.preflight import Report as Run
from melfa.sim.debug.preflight import preflight


@dataclass(frozen=True, slots=True)
class Submission:
    """A student's program and its points (None: the assignment's starter points)."""

    program: str
    points: str | None = None


@dataclass(frozen=True, slots=True)
class NotRun:
    """Why a check that needs a run has none: the message and the line to show."""

    message: str
    line: int | None


def grade(
    assignment: Assignment, submission: Submission, variant: str | int | None = None
) -> Report:
    """Grade `submission` against `assignment` for `variant`'s seed (None: as written)."""
    v = assignment.variant(variant)
    cell = variant_cell(assignment, v)
    points = submission.points
    if points is None:
        points = variant_points(assignment, v) or ""
    program = parse_tokens(tokenize(submission.program))
    project = check_project([submission.program], [points])
    errors = [d for d in project.programs[0] if d.is_error]
    point_errors = [d for d in project.points[0] if d.is_error]
    runs: dict[frozenset[tuple[int, int]], Run | NotRun] = {}

    def run(inputs: frozenset[tuple[int, int]] = frozenset()) -> Run | NotRun:
        if inputs not in runs:
            runs[inputs] = _simulate(
                assignment, submission.program, points, cell, inputs, errors, point_errors
            )
        return runs[inputs]

    results = [
        _judge(check, v, program, run, errors, point_errors) for check in assignment.spec.checks
    ]
    main = runs.get(frozenset())
    cycle = main.cycle_time if isinstance(main, Run) else None
    return Report.of(results, v.seed, cycle)


def _simulate(
    assignment: Assignment,
    program: str,
    points: str,
    cell: Cell,
    inputs: frozenset[tuple[int, int]],
    errors: list[Diagnostic],
    point_errors: list[Diagnostic],
) -> Run | NotRun:
    if errors:
        first = errors[0]
        return NotRun(f"{NOT_RUN}line {first.line}: {first.message}", first.line)
    if point_errors:
        first = point_errors[0]
        return NotRun(f"{NOT_RUN}the points file, line {first.line}: {first.message}", None)
    try:
        return preflight(
            program,
            points,
            cell=cell,
            inputs=sorted(inputs),
            max_time=assignment.spec.max_time_s,
        )
    except DebugError as exc:
        return NotRun(f"{NOT_RUN}{exc}", None)
    except Exception as exc:  # a bug of ours: a failed check that says so, never a traceback
        return NotRun(f"internal error in melfa's simulator (please report it): {exc!r}", None)


def _judge(
    check: Check,
    v: Variant,
    program: A.Program,
    run: Callable[..., Run | NotRun],
    errors: list[Diagnostic],
    point_errors: list[Diagnostic],
) -> CheckResult:
    check = follow(check, v)
    outcome: C.Outcome
    not_run = False
    match check:
        case Uses():
            outcome = C.uses(check, program)
        case Avoids():
            outcome = C.avoids(check, program)
        case NoErrors():
            outcome = _no_errors(errors, point_errors)
        case _:
            inputs = frozenset(check.inputs.items()) if isinstance(check, Io) else frozenset()
            got = run(inputs)
            if isinstance(got, NotRun):
                outcome, not_run = C.Outcome(False, got.message, got.line), True
            else:
                outcome = _on_run(check, got, program)
    return CheckResult(
        kind=check.kind,
        title=check.title or default_title(check),
        passed=outcome.passed,
        message=outcome.message,
        line=outcome.line,
        weight=check.weight,
        not_run=not_run,
    )


def _on_run(check: Check, run: Run, program: A.Program) -> C.Outcome:
    match check:
        case FinalPose():
            return C.final_pose(check, run)
        case Visits():
            return C.visits(check, run)
        case PartAt():
            return C.part_at(check, run)
        case Hand():
            return C.hand(check, run)
        case NoCollision():
            return C.no_collision(run)
        case CycleTime():
            return C.cycle_time(check, run)
        case Io():
            return C.io(check, run, program)
    raise AssertionError(f"{check.kind} is not judged on a run")  # pragma: no cover


def _no_errors(errors: list[Diagnostic], point_errors: list[Diagnostic]) -> C.Outcome:
    if errors:
        first = errors[0]
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        return C.Outcome(False, f"line {first.line}: {first.message}{more}", first.line)
    if point_errors:
        first = point_errors[0]
        return C.Outcome(False, f"the points file, line {first.line}: {first.message}")
    return C.Outcome(True, "melfa check finds no error")


def follow(check: Check, v: Variant) -> Check:
    """The check with its positions moved by its group's offset in variant `v`."""
    group = getattr(check, "follows", None)
    if group is None:
        return check
    by = v.offset(group)
    if by == (0.0, 0.0, 0.0):
        return check
    match check:
        case FinalPose():
            return check.model_copy(update={"pose": shifted(check.pose, by)})
        case Visits():
            return check.model_copy(update={"poses": tuple(shifted(p, by) for p in check.poses)})
        case PartAt():
            return check.model_copy(update={"position": shifted(check.position, by)})
        case Hand():
            return check.model_copy(update={"at": tuple(shifted(p, by) for p in check.at)})
    return check


def variant_cell(assignment: Assignment, v: Variant) -> Cell:
    """The assignment's cell with each group's parts and boxes moved by its offset."""
    cell = assignment.cell
    moves = {
        name: v.offset(group_name)
        for group_name, group in assignment.spec.variants.items()
        for name in group.parts
    }
    if not moves or not v.offsets:
        return cell
    boxes = tuple(
        dataclasses.replace(b, min=_add(b.min, moves[b.name]), max=_add(b.max, moves[b.name]))
        if b.name in moves
        else b
        for b in cell.boxes
    )
    parts = tuple(
        p.moved(_add(p.position, moves[p.name])) if p.name in moves else p for p in cell.parts
    )
    return dataclasses.replace(cell, boxes=boxes, parts=parts)


def _add(
    a: tuple[float, float, float], b: tuple[float, float, float]
) -> tuple[float, float, float]:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def variant_points(assignment: Assignment, v: Variant) -> str | None:
    """The starter points for variant `v` (each group's points moved), as a .POS text."""
    text = assignment.starter_points
    if text is None or not v.offsets:
        return text
    moves = {
        p.upper(): v.offset(name)
        for name, group in assignment.spec.variants.items()
        for p in group.points
    }
    out = text.splitlines()
    for point in parse_points(text).points:
        by = moves.get(point.key)
        if by is None or point.kind is not PointKind.POS or point.line < 1:
            continue
        x, y, z, *rest = point.values
        values = (_plus(x, by[0]), _plus(y, by[1]), _plus(z, by[2]), *rest)
        out[point.line - 1] = format_points(
            [PointDef(point.name, point.kind, values, point.fl1, point.fl2)]
        ).rstrip("\n")
    return "\n".join(out) + "\n"


def _plus(value: float | None, by: float) -> float | None:
    return None if value is None else value + by


def default_title(check: Check) -> str:
    """What a check checks, in words, when the instructor gave no title."""
    match check:
        case FinalPose():
            return f"the tool ends at {C.xyz_text(check.pose)}"
        case Visits():
            return f"the tool passes {_count(len(check.poses), 'pose')}"
        case PartAt():
            return f"{check.part} ends at {C.xyz_text(check.position)}"
        case Hand():
            verb = "opens" if check.action.value == "open" else "closes"
            return f"hand {check.hand} {verb} at {_count(len(check.at), 'place')}"
        case NoCollision():
            return "no collision, no pre-flight error"
        case CycleTime():
            return f"cycle time at most {check.max_s:g} s"
        case Io():
            given = ", ".join(f"M_IN({b}) = {v}" for b, v in sorted(check.inputs.items()))
            want = ", ".join(f"M_OUT({b}) = {v}" for b, v in sorted(check.outputs.items()))
            return f"with {given}: {want}" if given else want
        case Uses():
            return f"uses {', '.join(check.statements)}"
        case Avoids():
            return f"does not use {', '.join(check.statements)}"
        case NoErrors():
            return "no errors from melfa check"
    return CheckKind(check.kind).value  # pragma: no cover


def _count(n: int, noun: str) -> str:
    return f"{n} {noun}{'s' if n != 1 else ''}"
