"""The signed-in user's workspaces: list, create (named, optionally from an opened file),
rename and archive; read, save with a base revision (merged line by line with what was
saved since, and into the live document while the workspace is open: `web.coedit`),
history and restore, `.MB4`/`.POS` import and export. Staff open others' workspaces
read-only: every write here is refused until they choose *Edit as instructor*
(`PUT /{id}/staff-edit`, audited; `web.staff_edits`)."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, File, Form, Path, Query, UploadFile
from fastapi.responses import PlainTextResponse

from melfa.store import FileKind, SaveReason, Session, User, Workspace
from melfa.vocab.desk import DeskAction, visit_refusal
from melfa.web.context import WebContext
from melfa.web.convert import revision_info_out, revision_out, workspace_info, workspace_out
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.desk_audit import audit_desk
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import (
    RestoreIn,
    RevisionList,
    RevisionOut,
    SaveIn,
    SaveOut,
    StaffEditOut,
    WorkspaceCreateIn,
    WorkspaceInfo,
    WorkspaceList,
    WorkspaceOut,
    WorkspacePatchIn,
)

# Ids and numbers as the store keeps them (SQLite integers): one beyond is a 422 in the
# user's words, never an overflow inside the database driver.
RevisionNumber = Annotated[int, Path(ge=-(2**62), le=2**62, description="The revision's number")]
WorkspaceId = Annotated[int, Path(ge=-(2**62), le=2**62, description="The workspace's id")]

router = APIRouter(prefix="/api/workspaces", tags=["workspaces"], responses=ERROR_RESPONSES)

MAX_UPLOAD_BYTES = 2 * 1024 * 1024


async def open_workspace(context: WebContext, user: User, workspace_id: int) -> Workspace:
    """The workspace if ``user`` may open it; 404 / 403 otherwise."""
    if not 1 <= workspace_id <= 2**62:
        raise ApiError(404, "not-found", f"no workspace {workspace_id}")
    store = context.store
    workspace = await context.db(store.workspaces.get, workspace_id)
    store.workspaces.check_access(user, workspace)
    return workspace


async def writable_workspace(context: WebContext, session: Session, workspace_id: int) -> Workspace:
    """The workspace if this sign-in may change it: its members, or staff who chose *Edit
    as instructor* for it (`web.staff_edits`); 403 ``read-only`` otherwise."""
    workspace = await open_workspace(context, session.user, workspace_id)
    if not context.staff_edits.may_write(session, workspace):
        raise ApiError(403, "read-only", visit_refusal(workspace.owner))
    return workspace


async def default_workspace(context: WebContext, user: User) -> Workspace:
    """The group's workspace when the user is in a group (the thesis's lab groups),
    else their own."""
    store = context.store
    if user.group is not None:
        return await context.db(store.workspaces.group, user.group)
    return await context.db(store.workspaces.personal, user)


@router.get("", response_model=WorkspaceList, summary="Workspaces I may open")
async def list_workspaces(
    session: SessionDep,
    context: ContextDep,
    archived: Annotated[bool, Query(description="Also my archived workspaces")] = False,
) -> WorkspaceList:
    """Mine (the default one first), my group's shared one, and for staff every other."""
    user = session.user
    available = await context.db(context.store.workspaces.available_to, user)
    if archived:
        mine = await context.db(context.store.workspaces.mine, user, archived=True)
        known = {w.id for w in available}
        available += [w for w in mine if w.id not in known]
    default = await default_workspace(context, user)
    return WorkspaceList(default_id=default.id, workspaces=[workspace_info(w) for w in available])


@router.post("", response_model=WorkspaceOut, status_code=201, summary="New workspace")
async def create_workspace(
    body: WorkspaceCreateIn, session: SessionDep, context: ContextDep
) -> WorkspaceOut:
    """A new personal workspace of mine, empty or holding ``program`` and ``points`` (a file
    opened beside the current work). 409 ``already-exists`` if I have one of that name."""
    reason = SaveReason.IMPORT if body.from_file else SaveReason.SAVE
    ws = await context.db(
        context.store.workspaces.create,
        session.user,
        body.name,
        program=body.program,
        points=body.points,
        reason=reason,
    )
    return workspace_out(await context.db(context.store.workspaces.state, ws.id))


@router.patch("/{workspace_id}", response_model=WorkspaceInfo, summary="Rename or archive")
async def patch_workspace(
    workspace_id: WorkspaceId, body: WorkspacePatchIn, session: SessionDep, context: ContextDep
) -> WorkspaceInfo:
    """Rename (409 ``already-exists`` if the owner has one of that name) and/or archive:
    hidden from the switcher, never deleted; the default and shared ones stay."""
    ws = await writable_workspace(context, session, workspace_id)
    if body.name is not None:
        ws = await context.db(context.store.workspaces.rename, ws.id, body.name)
    if body.archived is not None:
        ws = await context.db(context.store.workspaces.archive, ws.id, body.archived)
    return workspace_info(ws)


@router.get("/{workspace_id}", response_model=WorkspaceOut, summary="Program and points")
async def get_workspace(
    workspace_id: WorkspaceId, session: SessionDep, context: ContextDep
) -> WorkspaceOut:
    ws = await open_workspace(context, session.user, workspace_id)
    return workspace_out(await context.db(context.store.workspaces.state, ws.id))


@router.put("/{workspace_id}", response_model=SaveOut, summary="Save (autosave)")
async def save_workspace(
    workspace_id: WorkspaceId, body: SaveIn, session: SessionDep, context: ContextDep
) -> SaveOut:
    """Store program and points on top of revision ``base``. When someone saved meanwhile
    (or is editing it live), this edit is merged with theirs line by line: no line of
    either is dropped, and the merged text is the revision returned. 409 ``save-conflict``
    (the current revision in ``error.detail.current``) only when revision ``base`` is no
    longer kept."""
    ws = await writable_workspace(context, session, workspace_id)
    result = await context.coedit.rest_write(
        ws.id,
        lambda: context.db(
            context.store.workspaces.save,
            ws.id,
            body.program,
            body.points,
            base=body.base,
            author=session.user,
            reason=SaveReason(body.reason),
        ),
    )
    for queue in context.queues.values():  # a queued text that changed is marked stale
        queue.workspace_saved(ws.id, result.revision.program, result.revision.points)
    return SaveOut(revision=revision_out(result.revision), created=result.created)


async def _audit_visit(
    context: WebContext, session: Session, ws: Workspace, action: DeskAction
) -> None:
    """A member of staff switched how they visit someone else's workspace: audited naming
    whose workspace it is and which."""
    await audit_desk(context, session, action, who=ws.owner, workspace=ws.name, workspace_id=ws.id)


@router.put("/{workspace_id}/staff-edit", response_model=StaffEditOut, summary="Edit as instructor")
async def edit_as_staff(
    workspace_id: WorkspaceId, session: SessionDep, context: ContextDep
) -> StaffEditOut:
    """Staff: change this workspace of someone else from now on, in this sign-in (it opens
    read-only). Audited; its owners see each edit live. A no-op for its own members."""
    ws = await open_workspace(context, session.user, workspace_id)
    if context.staff_edits.visiting(session, ws):
        context.staff_edits.grant(session, ws.id)
        await _audit_visit(context, session, ws, DeskAction.EDIT_AS_STAFF)
    return StaffEditOut(writable=True, visiting=context.staff_edits.visiting(session, ws))


@router.delete(
    "/{workspace_id}/staff-edit", response_model=StaffEditOut, summary="Back to read-only"
)
async def stop_editing_as_staff(
    workspace_id: WorkspaceId, session: SessionDep, context: ContextDep
) -> StaffEditOut:
    """Staff: read this workspace of someone else only, again (audited)."""
    ws = await open_workspace(context, session.user, workspace_id)
    visiting = context.staff_edits.visiting(session, ws)
    if visiting and context.staff_edits.editing(session, ws):
        context.staff_edits.revoke(session, ws.id)
        await _audit_visit(context, session, ws, DeskAction.READ_ONLY)
    return StaffEditOut(writable=not visiting, visiting=visiting)


@router.get("/{workspace_id}/revisions", response_model=RevisionList, summary="History")
async def list_revisions(
    workspace_id: WorkspaceId,
    session: SessionDep,
    context: ContextDep,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
    before: Annotated[int | None, Query(ge=1, le=2**62)] = None,
) -> RevisionList:
    ws = await open_workspace(context, session.user, workspace_id)
    infos = await context.db(
        context.store.workspaces.revisions, ws.id, limit=limit + 1, before=before
    )
    page = infos[:limit]
    more = len(infos) > limit
    return RevisionList(
        revisions=[revision_info_out(i) for i in page],
        next_before=page[-1].number if more and page else None,
    )


@router.get(
    "/{workspace_id}/revisions/{number}", response_model=RevisionOut, summary="One revision"
)
async def get_revision(
    workspace_id: WorkspaceId, number: RevisionNumber, session: SessionDep, context: ContextDep
) -> RevisionOut:
    ws = await open_workspace(context, session.user, workspace_id)
    return revision_out(await context.db(context.store.workspaces.revision, ws.id, number))


@router.post(
    "/{workspace_id}/revisions/{number}/restore",
    response_model=SaveOut,
    summary="Make an old revision current",
)
async def restore_revision(
    workspace_id: WorkspaceId,
    number: RevisionNumber,
    body: RestoreIn,
    session: SessionDep,
    context: ContextDep,
) -> SaveOut:
    ws = await writable_workspace(context, session, workspace_id)
    result = await context.coedit.rest_write(
        ws.id,
        lambda: context.db(
            context.store.workspaces.restore, ws.id, number, author=session.user, base=body.base
        ),
    )
    return SaveOut(revision=revision_out(result.revision), created=result.created)


@router.post("/{workspace_id}/import", response_model=SaveOut, summary="Import .MB4 or .POS")
async def import_file(
    workspace_id: WorkspaceId,
    session: SessionDep,
    context: ContextDep,
    file: Annotated[UploadFile, File(description="A .MB4 program or a .POS points file")],
    base: Annotated[int, Form(ge=0, le=2**62)],
) -> SaveOut:
    """Replaces the program (`.MB4`, step numbers stripped) or the points (`.POS`); the
    other half stays. A wrong extension is 422 ``wrong-extension``."""
    ws = await writable_workspace(context, session, workspace_id)
    filename = file.filename or ""
    data = await file.read(MAX_UPLOAD_BYTES + 1)
    if len(data) > MAX_UPLOAD_BYTES:
        raise ApiError(413, "too-large", f"{filename}: files above 2 MiB are not accepted")
    result = await context.coedit.rest_write(
        ws.id,
        lambda: context.db(
            context.store.workspaces.import_file,
            ws.id,
            filename,
            data,
            base=base,
            author=session.user,
        ),
    )
    return SaveOut(revision=revision_out(result.revision), created=result.created)


@router.get(
    "/{workspace_id}/export/{kind}",
    response_class=PlainTextResponse,
    summary="Export .MB4 (numbered) or .POS",
    responses={200: {"content": {"text/plain": {}}, "description": "The file"}},
)
async def export_file(
    workspace_id: WorkspaceId,
    kind: Literal["program", "points"],
    session: SessionDep,
    context: ContextDep,
) -> PlainTextResponse:
    ws = await open_workspace(context, session.user, workspace_id)
    file_kind = FileKind.PROGRAM if kind == "program" else FileKind.POINTS
    exported = await context.db(context.store.workspaces.export_file, ws.id, file_kind)
    return PlainTextResponse(
        exported.text.replace("\n", "\r\n"),
        headers={"Content-Disposition": f'attachment; filename="{exported.filename}"'},
    )


__all__ = ["default_workspace", "open_workspace", "router", "writable_workspace"]
