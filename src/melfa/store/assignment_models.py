"""Value types of assignments in the store: what the web layer gets back (pure, no I/O)."""

from __future__ import annotations

import enum
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from melfa.vocab.classroom import GradeKind

__all__ = [
    "Assignment",
    "AssignmentAction",
    "ClassRow",
    "Enrolment",
    "GradeKind",
    "Submission",
    "SubmissionSummary",
]


class AssignmentAction(enum.Enum):
    """What a user may want to do with an assignment (`assignment_access.allowed`)."""

    VIEW = "view"
    """Read its title, statement and checks."""
    WORK = "work"
    """Open it as a workspace, check and submit."""
    MANAGE = "manage"
    """Publish, export its folder, see the class view and every student's work."""


@dataclass(frozen=True, slots=True)
class Assignment:
    """A published assignment: the folder's files and how it was handed out."""

    id: int
    title: str
    files: dict[str, str]
    """``assignment.toml`` and the files it names, by their path in the folder."""
    group: str | None
    """The group it was published to; None: the whole class."""
    variants: bool
    """Each student gets a seed of their own (positions shift per student)."""
    due: datetime | None
    attempts: int | None
    """How many submissions each student may make; None: no limit."""
    author: str | None
    created: datetime


@dataclass(frozen=True, slots=True)
class Enrolment:
    """A student's copy of an assignment: their variant's seed and their workspace."""

    assignment_id: int
    user_id: int
    username: str
    seed: int
    workspace_id: int
    opened: datetime


@dataclass(frozen=True, slots=True)
class SubmissionSummary:
    """A graded revision without its report (for lists and the class view)."""

    id: int
    kind: GradeKind
    revision: int
    at: datetime
    passed: bool
    score: float
    preflight: bool | None
    """Whether the text passed pre-flight (no pre-flight error); None: not known."""
    max_score: float | None = None
    """What every check passing would score (from the report); None: not in the report."""
    checks_passed: int = 0
    """How many of the report's checks passed."""
    checks: int = 0
    """How many checks the report has."""
    fingerprint: str | None = None
    """The graded text's fingerprint as the lab robot would load it (a recorded run of the
    same fingerprint ran this text)."""


@dataclass(frozen=True, slots=True)
class Submission:
    """A graded revision with its report (the engine's JSON, as the student saw it)."""

    summary: SubmissionSummary
    assignment_id: int
    username: str
    workspace_id: int
    report: dict[str, Any]


@dataclass(frozen=True, slots=True)
class ClassRow:
    """One student of the class view: where they are with one assignment."""

    username: str
    display_name: str
    group: str | None
    enrolment: Enrolment | None
    """None: they have not opened it yet."""
    latest_check: SubmissionSummary | None
    """Their newest grading of either kind."""
    best: SubmissionSummary | None
    """Their best submission (highest score, then earliest)."""
    checks: int
    submissions: int
    attempts_left: int | None
    last_saved: datetime | None
    first_pass: datetime | None
    """When a check or submission of theirs first passed."""
    fingerprints: tuple[str, ...] = ()
    """The fingerprints of every text of theirs that was graded."""
