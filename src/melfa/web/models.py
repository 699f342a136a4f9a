"""Request and response bodies of the API. Inputs and outputs are separate models, and no
output model has a password hash in it (the store's public types have none)."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, FiniteFloat

# The live protocol's models, shared with REST (one shape for the state, the actor, an alarm).
from melfa.live.messages import ActorOut as ActorOut
from melfa.live.messages import AlarmOut as AlarmOut
from melfa.live.messages import StateOut as StateOut
from melfa.protocol.limits import HANDS, OVERRIDE_PERCENT
from melfa.store import MAX_TEXT_CHARS


def _encodable(text: str) -> str:
    """JSON may carry lone surrogates (``"\\ud800"``); nothing downstream can store them."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        raise ValueError("contains characters that are not valid Unicode") from None
    return text


Text = Annotated[str, AfterValidator(_encodable)]
LongText = Annotated[str, Field(max_length=MAX_TEXT_CHARS), AfterValidator(_encodable)]
ShortText = Annotated[str, Field(max_length=200), AfterValidator(_encodable)]
RoleName = Literal["admin", "instructor", "student"]


class Input(BaseModel):
    model_config = ConfigDict(extra="forbid")


# --- session & users -----------------------------------------------------------------------


class LoginIn(Input):
    username: ShortText
    password: Annotated[str, Field(max_length=1024), AfterValidator(_encodable)]


class OwnPasswordIn(Input):
    current: Annotated[str, Field(max_length=1024), AfterValidator(_encodable)]
    new: Annotated[str, Field(max_length=256), AfterValidator(_encodable)]


class UserOut(BaseModel):
    username: str
    display_name: str
    role: RoleName
    group: str | None
    created: datetime
    last_login: datetime | None
    disabled: bool


class SessionOut(BaseModel):
    user: UserOut
    csrf_token: str = Field(description="Send back as the X-CSRF-Token header.")
    expires: datetime


class UserCreateIn(Input):
    username: ShortText
    password: ShortText | None = Field(None, description="Generated (and returned) if absent.")
    role: RoleName = "student"
    group: ShortText | None = None
    display_name: ShortText = ""


class UserCreatedOut(BaseModel):
    user: UserOut
    password: str | None = Field(None, description="The generated password, shown once.")


class PasswordIn(Input):
    password: ShortText | None = Field(None, description="Generated (and returned) if absent.")


class PasswordOut(BaseModel):
    password: str | None = Field(None, description="The generated password, shown once.")


class UserList(BaseModel):
    users: list[UserOut]


class EnrolIn(Input):
    csv: LongText = Field(description="A class list: header username,name,group[,role][,password].")


class EnrolOut(BaseModel):
    created: list[str]
    skipped: list[str] = Field(description="Accounts that already existed (left as they were).")
    passwords: dict[str, str] = Field(
        description="Username to generated password, for the hand-out sheet; shown once."
    )


# --- workspaces ----------------------------------------------------------------------------


class WorkspaceInfo(BaseModel):
    id: int
    kind: Literal["personal", "group"]
    owner: str = Field(description="The owner's username, or the group's name.")
    name: str = Field(description="What its owner calls it (a group's: the group's name).")
    shared: bool = Field(description="A group's workspace: every member edits it.")
    archived: bool = Field(description="Hidden from the switcher; kept with its history.")


class WorkspaceList(BaseModel):
    default_id: int = Field(description="The group's workspace if the user has a group.")
    workspaces: list[WorkspaceInfo]


class WorkspaceCreateIn(Input):
    name: ShortText = Field(description="Unique among the user's workspaces (any case).")
    program: LongText = ""
    points: LongText = ""
    from_file: ShortText | None = Field(
        None, description="The file the content came from: the first revision is an import."
    )


class WorkspacePatchIn(Input):
    name: ShortText | None = Field(None, description="A new name.")
    archived: bool | None = Field(
        None, description="Hide from (true) or bring back to (false) the switcher."
    )


class WorkspaceOut(WorkspaceInfo):
    revision: int = Field(description="Send back as `base` with the next save (0: never saved).")
    program: str
    points: str


class SaveIn(Input):
    base: Annotated[int, Field(ge=0, le=2**62)]
    program: LongText
    points: LongText
    reason: Literal["autosave", "save"] = "autosave"


class RevisionInfoOut(BaseModel):
    number: int
    author: str | None
    created: datetime
    reason: Literal["autosave", "save", "import", "restore"]
    restored_from: int | None
    program_chars: int
    points_chars: int


class RevisionOut(BaseModel):
    number: int
    author: str | None
    created: datetime
    reason: Literal["autosave", "save", "import", "restore"]
    restored_from: int | None
    program: str
    points: str


class SaveOut(BaseModel):
    revision: RevisionOut
    created: bool = Field(description="False when the content was already stored.")


class StaffEditOut(BaseModel):
    writable: bool = Field(description="This sign-in may change the workspace now.")
    visiting: bool = Field(
        description="Staff looking at someone else's workspace (read-only unless they chose "
        "to edit it)."
    )


class RevisionList(BaseModel):
    revisions: list[RevisionInfoOut]
    next_before: int | None


class RestoreIn(Input):
    base: Annotated[int, Field(ge=0, le=2**62)] | None = None


# --- checking ------------------------------------------------------------------------------


class DiagnosticOut(BaseModel):
    """The shape of `melfa check --format json`."""

    line: int
    column: int
    end_line: int
    end_column: int
    severity: Literal["error", "warning", "info"]
    code: str | None
    message: str
    suggestion: str | None
    rule: str | None = None
    """The checker's stable rule name (docs/diagnostics.md); the IDE offers a fix for some."""
    replace: str | None = None
    """The text that fixes it written over its span (a misspelt point's close name)."""


class CheckIn(Input):
    program: LongText = ""
    points: LongText | None = Field(None, description="Points text; else the workspace's.")
    workspace_id: Annotated[int, Field(ge=1, le=2**62)] | None = None


class FileDiagnostics(BaseModel):
    diagnostics: list[DiagnosticOut]
    errors: int
    warnings: int


class CheckOut(BaseModel):
    program: FileDiagnostics
    points: FileDiagnostics


class NumberIn(Input):
    program: LongText
    start: Annotated[int, Field(ge=1, le=32767)] = 10
    step: Annotated[int, Field(ge=1, le=1000)] = 10


class StripIn(Input):
    program: LongText


class NumberOut(BaseModel):
    ok: bool = Field(description="False: `text` is the input unchanged; see diagnostics.")
    text: str
    diagnostics: list[DiagnosticOut]


# --- robot ---------------------------------------------------------------------------------


class SourceIn(Input):
    """Text from the request, else from the workspace (``workspace_id``, else the default)."""

    program: LongText | None = None
    points: LongText | None = None
    workspace_id: Annotated[int, Field(ge=1, le=2**62)] | None = None
    check: bool = Field(True, description="Refuse a program with errors before sending it.")


class UploadOut(BaseModel):
    items: int
    requests: int
    bytes_sent: int
    seconds: float
    step_lines: dict[int, int] | None = Field(
        None,
        description="Step number the controller reports -> line of the program as sent "
        "(`melfa.lang.plan.UploadPlan.step_lines`): the running line in the student's own text.",
    )
    fingerprint: str | None = Field(
        None,
        description="What the slot holds after the load: the program and points as sent "
        "(after points alone, the program with the positions it kept and these; null when "
        "that program is not known): the state's `slot.fingerprint` while the slot holds "
        "them, and what `run`'s `expect` names.",
    )


class SlotMatchIn(Input):
    """A program and its points, as an editor holds them."""

    program: LongText
    points: LongText = ""


class SlotMatchOut(BaseModel):
    """Whether a text is the one in the controller's slot."""

    same: bool = Field(
        description="The program and points are exactly what the slot holds (one fingerprint)."
    )
    fingerprint: str | None = Field(None, description="The slot's, when the same.")
    step_lines: dict[int, int] | None = Field(
        None, description="The slot's step number -> line of this text, when the same."
    )


SERVO_ON_FIELD = Field(
    False,
    description="The operator asked to move: switch the servo on first if it is off "
    "(audited). Otherwise a move with the servo off is refused with 409 "
    "controller-refused, number 2000, and nothing is sent.",
)


class RunIn(Input):
    servo_on: bool = SERVO_ON_FIELD
    expect: Annotated[str, Field(min_length=1, max_length=64)] | None = Field(
        None,
        description="The fingerprint of the program you mean to run (the state's "
        "`slot.fingerprint` you were shown): refused with 409 slot-changed when the slot "
        "holds another by now. Without it, whatever is loaded runs.",
    )


class ExecIn(Input):
    statement: Annotated[str, Field(min_length=1, max_length=240), AfterValidator(_encodable)]


class HandIn(Input):
    hand: Annotated[int, Field(ge=HANDS.start, le=HANDS[-1])] = 1
    action: Literal["open", "close", "toggle"]


class HandOut(BaseModel):
    hand: int
    open: bool


Six = Annotated[list[FiniteFloat], Field(min_length=6, max_length=6)]


class MoveIn(Input):
    """Exactly one of ``point`` (a name in the points), ``pose`` (X,Y,Z,A,B,C) or ``joints``."""

    point: Annotated[str, Field(max_length=16), AfterValidator(_encodable)] | None = None
    points: LongText | None = Field(
        None, description="Where to find ``point``; else the workspace's."
    )
    workspace_id: Annotated[int, Field(ge=1, le=2**62)] | None = None
    pose: Six | None = None
    joints: Six | None = None
    linear: bool = False
    servo_on: bool = SERVO_ON_FIELD
    flags: Annotated[list[Annotated[int, Field(ge=0, le=7)]], Field(min_length=2, max_length=2)] = [
        7,
        0,
    ]


class ServoIn(Input):
    on: bool


class OverrideIn(Input):
    percent: Annotated[int, Field(ge=OVERRIDE_PERCENT.start, le=OVERRIDE_PERCENT[-1])]


class OverrideOut(BaseModel):
    percent: int


class JogStepIn(Input):
    frame: Literal["tool", "xyz", "joint"]
    axis: Annotated[int, Field(ge=0, le=5)]
    direction: Literal[-1, 1]
    servo_on: bool = SERVO_ON_FIELD


class ValuesOut(BaseModel):
    names: list[str]
    values: list[float]


class TargetOut(BaseModel):
    """A robot the caller may drive (``id`` goes in ``?target=``)."""

    id: str = Field(description="`lab` (the lab's robot) or `mine` (your own simulator).")
    kind: str = Field(description="`lab` (shared, leased) or `private` (yours alone).")
    label: str = Field(description="What the header shows: `Lab RV-6S` / `My simulator`.")
    shared: bool
    robot: str = Field(description="The `--robot` the target runs on (`sim` for simulators).")
    exists: bool = Field(
        description="False until your simulator is first used (or after "
        "it was freed for being idle); using it makes it."
    )
    link: str | None


class TargetsOut(BaseModel):
    targets: list[TargetOut]
    idle_s: float = Field(description="A private simulator unused this long is freed.")


class LeaseOut(BaseModel):
    holder: ActorOut | None
    you: bool = Field(description="Whether you (any of your sessions) hold it.")
    since: datetime | None = Field(None, description="When the holder took it (UTC).")
    state: str | None = Field(
        None,
        description="The holder's connection: connected, no connection (taken over REST, "
        "no socket open), or disconnected, robot moving (keeps the lease until it stops).",
    )
    label: str = Field("free", description="For a header: 'alice — connected', 'free'.")
    connections: int = Field(0, description="The holder's open connections.")
    idle_expires_in_s: float | None = Field(
        None, description="Seconds until an idle lease ends (null: not counting down)."
    )


class Ok(BaseModel):
    ok: bool = True


# --- audit & health ------------------------------------------------------------------------


class AuditEntryOut(BaseModel):
    id: int
    at: datetime
    actor: str | None
    role: str | None
    action: str
    details: dict[str, Any]
    result: str


class AuditPageOut(BaseModel):
    entries: list[AuditEntryOut]
    next_before: int | None


class RobotHealth(BaseModel):
    link: str
    robot: str
    subscribers: int


class HealthOut(BaseModel):
    status: Literal["ok", "degraded"]
    version: str
    web: Literal["ok"]
    store: str
    robot: RobotHealth


# --- personal access tokens ----------------------------------------------------------------


class TokenIn(BaseModel):
    label: str = Field("", max_length=60, description="What the token is for.")


class TokenOut(BaseModel):
    id: int
    label: str
    created: datetime
    last_used: datetime | None


class TokenCreatedOut(BaseModel):
    token: str = Field(description="The token itself, shown only this once.")
    info: TokenOut


class TokenList(BaseModel):
    tokens: list[TokenOut]
