"""The words of assignments in the IDE: what a student reads beside their work, and the
instructor's class view (its columns, filters and CSV headings), in one place.

Pure: the store keeps `GradeKind` values, the web layer filters rows by `ClassFilter` and
writes the CSV with `COLUMN_WORDS`; the browser gets every table through ``/vocab.js``.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class GradeKind(enum.StrEnum):
    """Why a revision was graded: *Check my solution* (as often as wanted) or *Submit*
    (counted against the attempts)."""

    CHECK = "check"
    SUBMIT = "submit"


GRADE_WORDS: dict[GradeKind, str] = {
    GradeKind.CHECK: "Check my solution",
    GradeKind.SUBMIT: "Submit",
}
"""The buttons, and what a grading of each kind is called in a history."""

GRADED_WORDS: dict[GradeKind, str] = {
    GradeKind.CHECK: "Checked: {verdict}",
    GradeKind.SUBMIT: "Submitted: {verdict}",
}
"""What a grading's result says (``{verdict}``: ``every-check``, ``not-every-check`` or the
score): a submission that did not pass was still recorded, so it never reads "Submit: failed"."""


class ClassColumn(enum.StrEnum):
    """The class view's columns, in order (the CSV export has the same, same order)."""

    STUDENT = "student"
    GROUP = "group"
    VARIANT = "variant"
    LATEST = "latest"
    BEST = "best"
    ATTEMPTS = "attempts"
    LAST_SAVED = "last-saved"
    PREFLIGHT = "preflight"
    RAN = "ran"


COLUMN_WORDS: dict[ClassColumn, str] = {
    ClassColumn.STUDENT: "Student",
    ClassColumn.GROUP: "Group",
    ClassColumn.VARIANT: "Variant",
    ClassColumn.LATEST: "Latest check",
    ClassColumn.BEST: "Best submission",
    ClassColumn.ATTEMPTS: "Submissions",
    ClassColumn.LAST_SAVED: "Last saved",
    ClassColumn.PREFLIGHT: "Pre-flight",
    ClassColumn.RAN: "Ran on the arm",
}


class ClassFilter(enum.StrEnum):
    """Which students the class view lists."""

    ALL = "all"
    STUCK = "stuck"
    NOT_OPENED = "not-opened"
    NOT_SUBMITTED = "not-submitted"
    PASSED = "passed"


STUCK_AFTER_MIN = 30
"""Minutes after opening an assignment with no passing check: the student may need help."""


@dataclass(frozen=True, slots=True)
class FilterWords:
    label: str
    hint: str


FILTER_WORDS: dict[ClassFilter, FilterWords] = {
    ClassFilter.ALL: FilterWords("Everyone", "every student it was handed to"),
    ClassFilter.STUCK: FilterWords(
        f"No passing check after {STUCK_AFTER_MIN} min",
        f"opened it at least {STUCK_AFTER_MIN} minutes ago and nothing has passed yet",
    ),
    ClassFilter.NOT_OPENED: FilterWords("Not opened", "has not opened it yet"),
    ClassFilter.NOT_SUBMITTED: FilterWords("Not submitted", "opened it but has not submitted"),
    ClassFilter.PASSED: FilterWords("Passed", "a submission passed every check"),
}


RESULT_WORDS: dict[str, str] = {
    "passed": "passed",
    "failed": "failed",
    "every-check": "every check passed",
    "not-every-check": "not every check passed",
    "none": "not checked yet",
    "not-opened": "not opened",
    "preflight-ok": "passed",
    "preflight-failed": "errors",
    "unknown": "—",
    "no-limit": "no limit",
    "closed": "Submissions are closed",
    "attempts-left": "{left} of {total} submissions left",
    "attempts-unlimited": "Submit as often as you like",
    "attempts-unlimited-all": "no limit on submissions",
    "attempts-each": "{total} submissions each",
    "points": "{score} of {max} points",
    "due": "Due {due}",
    "variant": "Your variant: {words}",
    "score": "{passed} of {total} checks passed",
}
"""Short words the student's panel and the class view fill in (``{…}`` placeholders)."""


def summary_words(
    passed: bool, checks_passed: int, checks: int, score: float, max_score: float | None
) -> str:
    """How a grading is summed up, the same for the student and the instructor (their pane,
    the class view, its CSV): checks passed of checks, then the points when the checks
    have weights ("5 of 14 checks passed, 6 of 15 points")."""
    head = (
        RESULT_WORDS["every-check"]
        if passed
        else RESULT_WORDS["score"].format(passed=checks_passed, total=checks)
    )
    if max_score is None or (score == checks_passed and max_score == checks):
        return head
    return f"{head}, " + RESULT_WORDS["points"].format(score=f"{score:g}", max=f"{max_score:g}")


PANE_WORDS: dict[str, str] = {
    "button": "Assignments",
    "button-hint": "The assignments your instructor handed out",
    "list-title": "Assignments",
    "list-empty": "Nothing has been handed out yet.",
    "open": "Open",
    "continue": "Continue",
    "to-classroom": "Publish and class view ↗",
    "close": "Close",
    "hide": "Hide the assignment (the Assignments button brings it back)",
    "pane": "Assignment",
    "body": "The assignment's statement and checks",
    "checks": "Checks",
    "for-group": "for group {group}",
    "line": "line {line}",
    "line-hint": "Show this line in the editor",
    "checking": "Checking your solution on the simulator…",
    "submitting": "Submitting…",
    "not-saved-title": "Not checked yet",
    "not-saved": "Your edits are not saved yet. Once the status says Saved, try again.",
    "submitted-title": "Submitted",
    "submitted": "Revision {revision} is recorded. {left}.",
    "not-done": "{what}: not done",
    "read-failed": "Could not read the assignments",
    "open-failed": "Could not open the assignment",
    "check-failed": "Could not check your solution",
    "submit-failed": "Could not submit",
}
"""A student's assignment list and pane (``static/js/assign.js``)."""

CLASS_VIEW_WORDS: dict[str, str] = {
    "whole-class": "the whole class",
    "group": "group {group}",
    "for-whole-class": "For the whole class",
    "for-group": "For group {group}",
    "variants-on": "a variant per student",
    "published-by": "published by {author}",
    "open": "Open",
    "open-label": "Open {student}'s work (read-only)",
    "revision": "Revision {number}",
    "first-revision": "Revision {number}, the first.",
    "diff": "Revision {number} against revision {previous}: {lines} changed (− removed, + added).",
    "lines-one": "1 line",
    "lines-many": "{n} lines",
    "graded": "{kind} · revision {revision}",
    "score-hint": "Checks passed of checks; points are the weights of the checks that passed",
    "published-title": "Published",
    "published-class": "“{title}” is handed out to the whole class.",
    "published-group": "“{title}” is handed out to group {group}.",
    "choose-folder": "Choose the folder to see its title, checks and variants.",
    "cannot-publish": "This folder cannot be published yet:",
    "checks": "{count} checks: {titles}",
    "variant-groups": "Variant groups: {names}",
    "just-now": "just now",
    "minutes-ago": "{n} min ago",
    "hours-ago": "{n} h ago",
    "days-ago": "{n} d ago",
    "attempts": "{submissions} ({left} left)",
    "runs-one": "1 run",
    "runs-many": "{n} runs",
    "statement": "The statement",
    "view-failed": "Could not read the class view",
    "work-failed": "Could not open the student's work",
    "report-failed": "Could not read the report",
    "groups-failed": "Could not read the groups",
}
"""The instructor's class view (``static/js/classview.js``): ``attempts`` is a row's
submissions and the attempts left, ``runs-`` how often it ran on the arm; ``-failed``
names a request that failed (the server's reason follows)."""


__all__ = [
    "CLASS_VIEW_WORDS",
    "COLUMN_WORDS",
    "FILTER_WORDS",
    "GRADED_WORDS",
    "GRADE_WORDS",
    "PANE_WORDS",
    "RESULT_WORDS",
    "STUCK_AFTER_MIN",
    "ClassColumn",
    "ClassFilter",
    "FilterWords",
    "GradeKind",
    "summary_words",
]
