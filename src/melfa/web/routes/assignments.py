"""`/api/assignments`: exercises that check themselves (docs/api.md "Assignments").

Instructors read an assignment folder (files or a zip) and publish it to the class or a
group, export it again, and see the class view (one row per student, filters, CSV) and
every student's report. A student lists what was handed to them, opens one (it becomes a
workspace holding their variant's starter), checks their saved text as often as they like
and submits it within the attempts and the due date. Who may do what is decided once, in
`melfa.store.assignment_access`; the grading is `melfa.grade`'s."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, Path, Query, Request, UploadFile
from fastapi.responses import Response

from melfa.grade import Assignment as GradedAssignment
from melfa.grade import variant_cell
from melfa.sim.debug.cell import Cell
from melfa.store import (
    Assignment,
    AssignmentAction,
    Enrolment,
    User,
    allowed,
    require,
)
from melfa.vocab.classroom import ClassFilter, GradeKind
from melfa.web import classroom as C  # noqa: N812
from melfa.web.assignment_models import (
    AssignmentList,
    AssignmentOut,
    ClassOut,
    FolderIn,
    FolderOut,
    GradedOut,
    GradingReportOut,
    GroupsOut,
    HistoryOut,
    MineOut,
    PublishIn,
)
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, SessionDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.routes.pages import staff_page

router = APIRouter(prefix="/api/assignments", tags=["assignments"], responses=ERROR_RESPONSES)
pages = APIRouter(include_in_schema=False)

AssignmentId = Annotated[int, Path(ge=1, le=2**62, description="The assignment's id")]
GradingId = Annotated[int, Path(ge=1, le=2**62, description="The check's or submission's id")]


async def _assignment(
    context: WebContext, user: User, assignment_id: int, action: AssignmentAction
) -> Assignment:
    """The assignment if `user` may do `action` with it (404 / 403 otherwise)."""
    found = await context.db(context.store.assignments.get, assignment_id)
    require(user, action, found)
    return found


async def _engine(context: WebContext, assignment: Assignment) -> GradedAssignment:
    return await context.cpu(C.load, assignment.files)


async def _mine(context: WebContext, a: GradedAssignment, copy: Enrolment | None) -> MineOut | None:
    if copy is None:
        return None
    store = context.store.assignments
    history = await context.db(store.history, copy)
    left = await context.db(store.attempts_left, copy)
    return C.mine_out(a, copy, left, history)


async def cell_of_workspace(
    context: WebContext, user: User, workspace_id: int | None
) -> Cell | None:
    """The cell of `user`'s variant when `workspace_id` is their copy of an assignment
    (the debugger on their simulator runs in it); None for any other workspace."""
    if workspace_id is None:
        return None
    copies = await context.db(context.store.assignments.enrolments, user)
    copy = next((c for c in copies.values() if c.workspace_id == workspace_id), None)
    if copy is None:
        return None
    assignment = await context.db(context.store.assignments.get, copy.assignment_id)
    a = await _engine(context, assignment)
    return variant_cell(a, a.variant(copy.seed or None))


@router.get("", response_model=AssignmentList, summary="Assignments I may see")
async def list_assignments(session: SessionDep, context: ContextDep) -> AssignmentList:
    """Instructors: every assignment. Students: those handed to the class or their group,
    each with their copy once opened (workspace, variant, attempts left, latest result)."""
    user = session.user
    store = context.store.assignments
    every = await context.db(store.listed)
    visible = [a for a in every if allowed(user, AssignmentAction.VIEW, a)]
    copies = await context.db(store.enrolments, user)
    out = []
    for a in visible:
        copy = copies.get(a.id)
        mine = await _mine(context, await _engine(context, a), copy) if copy else None
        out.append(C.info_out(a, mine))
    return AssignmentList(assignments=out)


@router.get("/groups", response_model=GroupsOut, summary="Groups to publish to")
async def groups(session: StaffDep, context: ContextDep) -> GroupsOut:
    found = await context.db(context.store.accounts.list_groups)
    return GroupsOut(groups=[g.name for g in found])


@router.post("/folder", response_model=FolderOut, summary="Read an assignment folder")
async def read_folder(body: FolderIn, session: StaffDep, context: ContextDep) -> FolderOut:
    """What a folder's files hold (title, statement, checks, variants) or every problem
    with it, for the publish form; nothing is stored."""
    return await context.cpu(C.folder_out, body.files)


@router.post("/folder.zip", response_model=FolderOut, summary="Read a zipped folder")
async def read_zip(
    session: StaffDep,
    context: ContextDep,
    file: Annotated[UploadFile, File(description="The assignment folder as a .zip")],
) -> FolderOut:
    data = await file.read(C.MAX_ZIP_BYTES + 1)
    if len(data) > C.MAX_ZIP_BYTES:
        raise ApiError(413, "too-large", "an assignment folder holds at most 4 MiB")
    files = await context.cpu(C.unzip, data)
    return await context.cpu(C.folder_out, files)


@router.post("", response_model=AssignmentOut, status_code=201, summary="Publish")
async def publish(body: PublishIn, session: StaffDep, context: ContextDep) -> AssignmentOut:
    """Hand the folder out to the class (``group`` null) or one group. Due date and
    attempts default to the assignment.toml's. A broken folder is 422
    ``invalid-assignment`` with every problem in ``detail.problems``."""
    a = await context.cpu(C.load, body.files)
    made = await context.db(
        context.store.assignments.publish,
        session.user,
        a.title,
        body.files,
        group=body.group,
        variants=body.variants,
        due=body.due if body.due is not None else C.due_of(a),
        attempts=body.attempts if body.attempts is not None else a.spec.attempts,
    )
    return await _detail(context, made, a, None)


async def _detail(
    context: WebContext, assignment: Assignment, a: GradedAssignment, copy: Enrolment | None
) -> AssignmentOut:
    info = C.info_out(assignment, await _mine(context, a, copy))
    return AssignmentOut(
        **info.model_dump(),
        statement_html=C.statement_html(a.statement),
        checks=C.checks_of(a),
        cell=C.cell_of(a, copy.seed if copy else 0),
    )


@router.get("/{assignment_id}", response_model=AssignmentOut, summary="One assignment")
async def get_assignment(
    assignment_id: AssignmentId, session: SessionDep, context: ContextDep
) -> AssignmentOut:
    """Its statement (HTML), checks, and the caller's copy and variant's cell once opened."""
    assignment = await _assignment(context, session.user, assignment_id, AssignmentAction.VIEW)
    copy = await context.db(context.store.assignments.enrolment, assignment.id, session.user)
    return await _detail(context, assignment, await _engine(context, assignment), copy)


@router.post("/{assignment_id}/open", response_model=AssignmentOut, summary="Open as workspace")
async def open_assignment(
    assignment_id: AssignmentId, session: SessionDep, context: ContextDep
) -> AssignmentOut:
    """The caller's copy, made the first time: a seed and a workspace named after the
    assignment holding the starter of their variant. Opening again changes nothing."""
    assignment = await _assignment(context, session.user, assignment_id, AssignmentAction.WORK)
    a = await _engine(context, assignment)
    copy = await context.db(
        context.store.assignments.open,
        assignment.id,
        session.user,
        lambda seed: C.starter(a, seed),
        lambda taken: C.fresh_seed(a, taken),
    )
    return await _detail(context, assignment, a, copy)


async def _grade(context: WebContext, user: User, assignment_id: int, kind: GradeKind) -> GradedOut:
    assignment = await _assignment(context, user, assignment_id, AssignmentAction.WORK)
    store = context.store
    copy = await context.db(store.assignments.enrolment, assignment.id, user)
    if copy is None:
        raise ApiError(409, "not-opened", "open the assignment first: it makes your workspace")
    a = await _engine(context, assignment)
    state = await context.db(store.workspaces.state, copy.workspace_id)
    out = await context.cpu(C.graded, a, copy.seed, state.program, state.points)
    summary = await context.db(
        store.assignments.record,
        copy,
        kind,
        state.revision,
        passed=out.report.passed,
        score=out.report.score,
        preflight=out.preflight,
        report=out.report.model_dump(mode="json"),
        fingerprint=out.fingerprint,
    )
    left = await context.db(store.assignments.attempts_left, copy)
    return GradedOut(grading=C.grading_out(summary), report=out.report, attempts_left=left)


@router.post("/{assignment_id}/check", response_model=GradedOut, summary="Check my solution")
async def check(assignment_id: AssignmentId, session: SessionDep, context: ContextDep) -> GradedOut:
    """Grade the newest saved revision of the caller's workspace for their variant: every
    check passed or failed with the line that caused a failure. As often as wanted."""
    return await _grade(context, session.user, assignment_id, GradeKind.CHECK)


@router.post("/{assignment_id}/submit", response_model=GradedOut, summary="Submit")
async def submit(
    assignment_id: AssignmentId, session: SessionDep, context: ContextDep
) -> GradedOut:
    """Grade and record the newest saved revision as a submission; 422
    ``submissions-closed`` after the due date or once every attempt is used."""
    return await _grade(context, session.user, assignment_id, GradeKind.SUBMIT)


@router.get("/{assignment_id}/history", response_model=HistoryOut, summary="Checks, submissions")
async def history(
    assignment_id: AssignmentId,
    session: SessionDep,
    context: ContextDep,
    student: Annotated[str | None, Query(max_length=200)] = None,
) -> HistoryOut:
    """The caller's gradings, newest first; instructors name any ``student``."""
    user = session.user
    action = AssignmentAction.WORK if student is None else AssignmentAction.MANAGE
    assignment = await _assignment(context, user, assignment_id, action)
    whose = user if student is None else await context.db(context.store.accounts.get_user, student)
    copy = await context.db(context.store.assignments.enrolment, assignment.id, whose)
    gradings = [] if copy is None else await context.db(context.store.assignments.history, copy)
    return HistoryOut(gradings=[C.grading_out(g) for g in gradings])


@router.get(
    "/{assignment_id}/gradings/{grading_id}", response_model=GradingReportOut, summary="One report"
)
async def report(
    assignment_id: AssignmentId, grading_id: GradingId, session: SessionDep, context: ContextDep
) -> GradingReportOut:
    """A check's or submission's report: the student's own, or any for instructors."""
    user = session.user
    assignment = await _assignment(context, user, assignment_id, AssignmentAction.VIEW)
    found = await context.db(context.store.assignments.submission, assignment.id, grading_id)
    if found.username.lower() != user.username.lower():
        require(user, AssignmentAction.MANAGE, assignment)
    return GradingReportOut(
        grading=C.grading_out(found.summary),
        student=found.username,
        workspace_id=found.workspace_id,
        report=found.report,
    )


@router.get("/{assignment_id}/export", summary="The folder as a zip")
async def export(assignment_id: AssignmentId, session: StaffDep, context: ContextDep) -> Response:
    assignment = await _assignment(context, session.user, assignment_id, AssignmentAction.MANAGE)
    data = await context.cpu(C.zipped, assignment.title, assignment.files)
    return Response(
        data,
        media_type="application/zip",
        headers={"Content-Disposition": f'attachment; filename="{C.stem(assignment.title)}.zip"'},
    )


async def _class(
    context: WebContext, user: User, assignment_id: int, which: ClassFilter
) -> ClassOut:
    assignment = await _assignment(context, user, assignment_id, AssignmentAction.MANAGE)
    rows = await context.db(context.store.assignments.class_rows, assignment.id)
    now = context.store.db.clock()
    out = []
    for r in rows:
        if not C.matches(r, which, now):
            continue
        runs = []
        if r.enrolment is not None and r.fingerprints:
            runs = await context.db(context.store.runs.list, r.username, limit=RUNS_READ)
        out.append(C.row_out(r, now, C.ran_on_arm(r, runs)))
    return ClassOut(assignment=C.info_out(assignment), filter=which, now=now, rows=out)


RUNS_READ = 200
"""A student's newest recorded runs read for the class view's "ran on the arm" column."""

FilterQuery = Annotated[ClassFilter, Query(description="Which students to list")]


@router.get("/{assignment_id}/class", response_model=ClassOut, summary="The class view")
async def class_view(
    assignment_id: AssignmentId,
    session: StaffDep,
    context: ContextDep,
    filter: FilterQuery = ClassFilter.ALL,
) -> ClassOut:
    """One row per student it was handed to: their copy and variant, latest check, best
    submission, submissions and attempts left, last save, first pass, pre-flight."""
    return await _class(context, session.user, assignment_id, filter)


@router.get("/{assignment_id}/class.csv", summary="The class view as CSV")
async def class_csv(
    assignment_id: AssignmentId,
    session: StaffDep,
    context: ContextDep,
    filter: FilterQuery = ClassFilter.ALL,
) -> Response:
    view = await _class(context, session.user, assignment_id, filter)
    stem = C.stem(view.assignment.title)
    return Response(
        C.class_csv(view.rows),
        media_type="text/csv; charset=utf-8",
        headers={"Content-Disposition": f'attachment; filename="{stem}-class.csv"'},
    )


@pages.get("/classroom", response_model=None)
async def classroom_page(request: Request) -> Response:
    """The instructor's page: publish, and the class view of each assignment."""
    return await staff_page(
        request, "classroom.html", "<p>Only instructors and admins see the class view.</p>"
    )


__all__ = ["cell_of_workspace", "pages", "router"]
