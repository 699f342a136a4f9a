"""Request and response bodies of `/api/assignments` (docs/api.md "Assignments"): typed
records from the store and the grading engine to the browser. A grading's report is the
engine's own `melfa.grade.Report`, sent as it is."""

from __future__ import annotations

from datetime import datetime
from typing import Annotated, Any

from pydantic import BaseModel, Field

from melfa.grade import CheckKind, Report
from melfa.store import MAX_NAME_CHARS
from melfa.vocab.classroom import ClassFilter, GradeKind
from melfa.web.models import Input, LongText, ShortText

FileName = Annotated[str, Field(min_length=1, max_length=200)]


class FolderIn(Input):
    """An assignment folder as files: ``assignment.toml`` and the files it names."""

    files: dict[FileName, LongText] = Field(max_length=32)


class PublishIn(FolderIn):
    group: ShortText | None = Field(None, description="The group it is for; null: the class.")
    variants: bool = Field(False, description="A seed per student shifts the positions.")
    due: datetime | None = Field(None, description="Null: the assignment.toml's due, if any.")
    attempts: Annotated[int, Field(ge=1, le=1000)] | None = Field(
        None, description="Submissions per student; null: the assignment.toml's, else no limit."
    )


class Problem(BaseModel):
    file: str
    where: str
    message: str


class GroupsOut(BaseModel):
    groups: list[str]


class AssignmentCheckOut(BaseModel):
    kind: CheckKind
    title: str


class FolderOut(BaseModel):
    """What an imported folder holds (its files for the publish form) and what is wrong."""

    files: dict[str, str]
    title: str | None
    statement_html: str | None
    checks: list[AssignmentCheckOut]
    variants: list[str] = Field(description="The names of its variant groups.")
    due: datetime | None
    attempts: int | None
    problems: list[Problem]


class GradingOut(BaseModel):
    """One check or submission, without its report."""

    id: int
    kind: GradeKind
    revision: int
    at: datetime
    passed: bool
    score: float
    max_score: float | None = Field(description="The score with every check passed.")
    preflight: bool | None = Field(description="The text passed pre-flight; null: unknown.")
    checks_passed: int = Field(description="How many checks passed.")
    checks: int = Field(description="How many checks were graded.")
    summary: str = Field(description="The grading in words, as student and instructor read it.")


class MineOut(BaseModel):
    """A student's copy: their workspace, variant and where they stand."""

    workspace_id: int
    seed: int
    variant: str = Field(description="Where this student's positions moved, in words.")
    opened: datetime
    attempts_left: int | None
    latest: GradingOut | None
    best: GradingOut | None


class AssignmentInfo(BaseModel):
    id: int
    title: Annotated[str, Field(max_length=MAX_NAME_CHARS)]
    group: str | None
    variants: bool
    due: datetime | None
    attempts: int | None
    author: str | None
    created: datetime
    mine: MineOut | None = Field(None, description="The caller's copy, once opened.")


class AssignmentList(BaseModel):
    assignments: list[AssignmentInfo]


class AssignmentOut(AssignmentInfo):
    statement_html: str = Field(description="The statement, Markdown rendered (no raw HTML).")
    checks: list[AssignmentCheckOut]
    cell: dict[str, Any] = Field(description="The cell of the caller's variant.")


class GradedOut(BaseModel):
    """A grading just made: its record, the engine's report, what is left."""

    grading: GradingOut
    report: Report
    attempts_left: int | None


class HistoryOut(BaseModel):
    gradings: list[GradingOut]


class GradingReportOut(BaseModel):
    grading: GradingOut
    student: str
    workspace_id: int
    report: dict[str, Any]


class ClassRowOut(BaseModel):
    student: str
    display_name: str
    group: str | None
    seed: int | None
    workspace_id: int | None
    opened: datetime | None
    latest: GradingOut | None
    best: GradingOut | None
    checks: int
    submissions: int
    attempts_left: int | None
    last_saved: datetime | None
    first_pass: datetime | None
    stuck: bool = Field(description="Opened long enough ago with no passing check yet.")
    ran_on_arm: int = Field(
        description="Recorded runs on the lab robot, since opening, of a text of theirs that "
        "was graded (the same fingerprint)."
    )


class ClassOut(BaseModel):
    assignment: AssignmentInfo
    filter: ClassFilter
    now: datetime = Field(description="The server's time the rows were read at.")
    rows: list[ClassRowOut]


__all__ = [
    "AssignmentCheckOut",
    "AssignmentInfo",
    "AssignmentList",
    "AssignmentOut",
    "ClassOut",
    "ClassRowOut",
    "FolderIn",
    "FolderOut",
    "GradedOut",
    "GradingOut",
    "GradingReportOut",
    "GroupsOut",
    "HistoryOut",
    "MineOut",
    "Problem",
    "PublishIn",
]
