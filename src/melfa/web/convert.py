"""From the store's and the service's values to the API's models (one place)."""

from __future__ import annotations

import dataclasses
from typing import Any

from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.live.messages import SlotOut
from melfa.protocol.advice import FIX_LABELS, Fix, advice_for, is_user_error
from melfa.service import Actor, StateSnapshot, event_to_dict
from melfa.store import Revision, RevisionInfo, User, Workspace, WorkspaceState
from melfa.web.models import (
    ActorOut,
    DiagnosticOut,
    FileDiagnostics,
    RevisionInfoOut,
    RevisionOut,
    StateOut,
    TargetOut,
    UserOut,
    WorkspaceInfo,
    WorkspaceOut,
)
from melfa.web.targets import Target


def user_out(user: User) -> UserOut:
    return UserOut(
        username=user.username,
        display_name=user.display_name,
        role=user.role.value,
        group=user.group,
        created=user.created,
        last_login=user.last_login,
        disabled=user.disabled,
    )


def workspace_info(ws: Workspace) -> WorkspaceInfo:
    return WorkspaceInfo(
        id=ws.id,
        kind=ws.kind.value,
        owner=ws.owner,
        name=ws.name or ws.owner,
        shared=ws.shared,
        archived=ws.archived,
    )


def workspace_out(state: WorkspaceState) -> WorkspaceOut:
    return WorkspaceOut(
        **workspace_info(state.workspace).model_dump(),
        revision=state.revision,
        program=state.program,
        points=state.points,
    )


def revision_out(rev: Revision) -> RevisionOut:
    return RevisionOut(
        number=rev.number,
        author=rev.author,
        created=rev.created,
        reason=rev.reason.value,
        restored_from=rev.restored_from,
        program=rev.program,
        points=rev.points,
    )


def revision_info_out(info: RevisionInfo) -> RevisionInfoOut:
    return RevisionInfoOut(
        number=info.number,
        author=info.author,
        created=info.created,
        reason=info.reason.value,
        restored_from=info.restored_from,
        program_chars=info.program_chars,
        points_chars=info.points_chars,
    )


def diagnostics_out(diagnostics: list[Diagnostic]) -> FileDiagnostics:
    return FileDiagnostics(
        diagnostics=[DiagnosticOut.model_validate(d.to_json()) for d in diagnostics],
        errors=sum(1 for d in diagnostics if d.severity is Severity.ERROR),
        warnings=sum(1 for d in diagnostics if d.severity is Severity.WARNING),
    )


def actor_out(actor: Actor | None) -> ActorOut | None:
    return None if actor is None else ActorOut(user=actor.user, role=actor.role.value)


def actor_dict(actor: Actor | None) -> dict[str, str] | None:
    return None if actor is None else {"user": actor.user, "role": actor.role.value}


def state_dict(snapshot: StateSnapshot) -> dict[str, Any]:
    """A snapshot as JSON (the ``state`` WebSocket message without its ``type``)."""
    slot = snapshot.slot
    # The slot is told as `SlotOut` says: its lines and step map stay in the service.
    out = event_to_dict(snapshot if slot is None else dataclasses.replace(snapshot, slot=None))
    if slot is not None:
        out["slot"] = SlotOut.model_validate(slot, from_attributes=True).model_dump(mode="json")
    for key in ("name", "actor"):
        out.pop(key, None)
    if snapshot.alarm is not None:
        # An active alarm says what to do about it (reset-alarm where that helps).
        advice = advice_for(snapshot.alarm.number)
        fix = advice.to_json()
        if fix["fix"] is None or fix["fix"] == Fix.SERVO_ON_RETRY.value:
            fix.update(fix=Fix.RESET_ALARM.value, fix_label=FIX_LABELS[Fix.RESET_ALARM])
        out["alarm"].update(fix, own=is_user_error(snapshot.alarm.number))
    return out


def state_out(snapshot: StateSnapshot) -> StateOut:
    return StateOut.model_validate(state_dict(snapshot))


__all__ = [
    "actor_dict",
    "actor_out",
    "diagnostics_out",
    "revision_info_out",
    "revision_out",
    "state_dict",
    "state_out",
    "user_out",
    "workspace_info",
    "workspace_out",
]


def target_out(target: Target, *, robot: str, exists: bool = True) -> TargetOut:
    """How a client names and shows a target (the header's label and colour come from
    ``kind``)."""
    return TargetOut(
        id=target.id,
        kind=target.kind.value,
        label=target.label,
        shared=target.shared,
        robot=robot,
        exists=exists,
        link=target.service.link_status.value if exists else None,
    )


def target_dict(target: Target) -> dict[str, Any]:
    return {"id": target.id, "kind": target.kind.value, "label": target.label}
