"""Assignments: published folders, each student's copy (seed and workspace), and every
check and submission with the revision it graded.

Rules (docs/store.md "Assignments"):

* An assignment keeps its folder's files as they were imported (``assignment.toml`` and the
  files it names), so exporting gives the same folder back. The store never reads them: the
  grading engine (`melfa.grade`) does.
* A student's copy is made once, the first time they open the assignment: a seed of their
  own when it has variants (never one already handed out; 0 for everybody without variants)
  and a personal workspace named after it holding the starter text of their variant.
* A check or submission records the workspace revision it graded, its report, and whether
  it passed; a submission is refused once the attempts are used or the due date has passed.
  Nothing is ever deleted.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Callable, Mapping
from datetime import datetime
from typing import Any

from melfa.store.assignment_models import (
    Assignment,
    ClassRow,
    Enrolment,
    GradeKind,
    Submission,
    SubmissionSummary,
)
from melfa.store.db import Database
from melfa.store.errors import AlreadyExists, InvalidValue, NotFound
from melfa.store.models import SaveReason, User
from melfa.store.rows import record
from melfa.store.timeutil import from_text, from_text_or_none, to_text
from melfa.store.workspace_names import MAX_NAME_CHARS, clean_name
from melfa.store.workspaces import MAX_TEXT_CHARS, Workspaces

__all__ = ["MAX_FILES", "AssignmentClosed", "Assignments", "SeedChooser", "Starter", "next_seed"]

MAX_FILES = 32
"""Files in one assignment folder: the toml, a statement, starter texts, a cell, solutions."""

Starter = Callable[[int], tuple[str, str]]
"""The starter program and points of the variant with a seed (the engine computes them)."""

SeedChooser = Callable[[list[int]], int]
"""The seed of a new student's copy, given the seeds already handed out (the web layer
picks one whose positions differ from theirs where the variants allow)."""


def next_seed(taken: list[int]) -> int:
    """1, 2, 3 … in the order students open the assignment."""
    return max(taken, default=0) + 1


class AssignmentClosed(InvalidValue):
    """A submission after the due date or once every attempt is used."""

    def __init__(self, message: str) -> None:
        super().__init__("submission", message)


_SELECT = """
    SELECT a.id, a.title, a.files, a.variants, a.due, a.attempts, a.author, a.created,
           g.name AS "group"
    FROM assignments AS a LEFT JOIN groups AS g ON g.id = a.group_id
"""


def _assignment(row: sqlite3.Row) -> Assignment:
    return record(
        Assignment,
        row,
        files=json.loads,
        variants=bool,
        due=from_text_or_none,
        created=from_text,
    )


def _enrolment(row: sqlite3.Row) -> Enrolment:
    return record(Enrolment, row, opened=from_text)


_GRADED = (
    "*, json_extract(report, '$.max_score') AS max_score,"
    " (SELECT count(*) FROM json_each(report, '$.checks')) AS checks_total,"
    " (SELECT count(*) FROM json_each(report, '$.checks')"
    " WHERE json_extract(value, '$.passed')) AS checks_passed"
)
"""A grading's columns, its report's highest score (the engine's ``max_score``) and how
many of its checks passed, of how many."""


def _summary(row: sqlite3.Row) -> SubmissionSummary:
    preflight = row["preflight"]
    return SubmissionSummary(
        id=row["id"],
        kind=GradeKind(row["kind"]),
        revision=row["revision"],
        at=from_text(row["at"]),
        passed=bool(row["passed"]),
        score=float(row["score"]),
        preflight=None if preflight is None else bool(preflight),
        fingerprint=row["fingerprint"],
        max_score=None if row["max_score"] is None else float(row["max_score"]),
        checks_passed=row["checks_passed"],
        checks=row["checks_total"],
    )


def _check_files(files: Mapping[str, str]) -> dict[str, str]:
    if not files:
        raise InvalidValue("files", "an assignment folder needs at least its assignment.toml")
    if len(files) > MAX_FILES:
        raise InvalidValue("files", f"holds {len(files)} files; at most {MAX_FILES} are kept")
    for name, text in files.items():
        if len(text) > MAX_TEXT_CHARS:
            raise InvalidValue(name, f"is {len(text)} characters; at most {MAX_TEXT_CHARS}")
    return dict(files)


_ENROLMENT = """
    SELECT s.*, u.username FROM assignment_students AS s JOIN users AS u ON u.id = s.user_id
"""


class Assignments:
    """Assignments, students' copies and gradings in one `Database`."""

    def __init__(self, db: Database, workspaces: Workspaces) -> None:
        self.db = db
        self.workspaces = workspaces

    # --- publishing -----------------------------------------------------------------------

    def publish(
        self,
        author: User,
        title: str,
        files: Mapping[str, str],
        *,
        group: str | None = None,
        variants: bool = False,
        due: datetime | None = None,
        attempts: int | None = None,
    ) -> Assignment:
        """Hand an assignment out to the class (``group`` None) or one group. The caller
        (the web layer) has checked the folder with the grading engine."""
        cleaned = clean_name(title)
        stored = _check_files(files)
        if attempts is not None and attempts < 1:
            raise InvalidValue("attempts", "must be at least 1 (or no limit)")
        now = to_text(self.db.clock())

        def write(conn: sqlite3.Connection) -> Assignment:
            group_id = None
            if group is not None:
                row = conn.execute("SELECT id FROM groups WHERE name = ?", (group,)).fetchone()
                if row is None:
                    raise NotFound(f"no group {group!r}")
                group_id = row["id"]
            cursor = conn.execute(
                "INSERT INTO assignments (title, files, group_id, variants, due, attempts,"
                " author, created) VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    cleaned,
                    json.dumps(stored),
                    group_id,
                    int(variants),
                    None if due is None else to_text(due),
                    attempts,
                    author.username,
                    now,
                ),
            )
            return _by_id(conn, int(cursor.lastrowid or 0))

        return self.db.write(write)

    def get(self, assignment_id: int) -> Assignment:
        return self.db.read(lambda c: _by_id(c, assignment_id))

    def listed(self) -> list[Assignment]:
        """Every assignment, newest first (whom each is for is `assignment_access`'s
        question)."""
        rows = self.db.read(lambda c: c.execute(_SELECT + " ORDER BY a.id DESC").fetchall())
        return [_assignment(r) for r in rows]

    # --- a student's copy -----------------------------------------------------------------

    def enrolment(self, assignment_id: int, user: User) -> Enrolment | None:
        row = self.db.read(
            lambda c: c.execute(
                _ENROLMENT + " WHERE s.assignment_id = ? AND s.user_id = ?",
                (assignment_id, user.id),
            ).fetchone()
        )
        return None if row is None else _enrolment(row)

    def enrolments(self, user: User) -> dict[int, Enrolment]:
        """Every copy `user` has, by assignment id."""
        rows = self.db.read(
            lambda c: c.execute(_ENROLMENT + " WHERE s.user_id = ?", (user.id,)).fetchall()
        )
        return {r["assignment_id"]: _enrolment(r) for r in rows}

    def open(
        self,
        assignment_id: int,
        user: User,
        starter: Starter,
        choose_seed: SeedChooser = next_seed,
    ) -> Enrolment:
        """The user's copy, made on first use: a seed (``choose_seed`` of those taken, when
        the assignment has variants; else 0), and a workspace named after the assignment
        holding ``starter(seed)`` (program, points)."""
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> Enrolment:
            found = conn.execute(
                _ENROLMENT + " WHERE s.assignment_id = ? AND s.user_id = ?",
                (assignment_id, user.id),
            ).fetchone()
            if found is not None:
                return _enrolment(found)
            assignment = _by_id(conn, assignment_id)
            seed = 0
            if assignment.variants:
                taken = conn.execute(
                    "SELECT seed FROM assignment_students WHERE assignment_id = ?",
                    (assignment_id,),
                ).fetchall()
                seed = choose_seed([int(r[0]) for r in taken])
            program, points = starter(seed)
            workspace = None
            for n in range(1, 100):
                name = assignment.title if n == 1 else f"{assignment.title} ({n})"
                try:
                    workspace = self.workspaces.create(
                        user,
                        name[:MAX_NAME_CHARS],
                        program=program,
                        points=points,
                        reason=SaveReason.IMPORT,
                    )
                    break
                except AlreadyExists:
                    continue
            if workspace is None:
                raise AlreadyExists(f"{user.username} has too many workspaces named like it")
            conn.execute(
                "INSERT INTO assignment_students (assignment_id, user_id, seed, workspace_id,"
                " opened) VALUES (?, ?, ?, ?, ?)",
                (assignment_id, user.id, seed, workspace.id, to_text(now)),
            )
            return _enrolment(
                conn.execute(
                    _ENROLMENT + " WHERE s.assignment_id = ? AND s.user_id = ?",
                    (assignment_id, user.id),
                ).fetchone()
            )

        return self.db.write(write)

    # --- gradings -------------------------------------------------------------------------

    def record(
        self,
        enrolment: Enrolment,
        kind: GradeKind,
        revision: int,
        *,
        passed: bool,
        score: float,
        preflight: bool | None,
        report: Mapping[str, Any],
        fingerprint: str | None = None,
    ) -> SubmissionSummary:
        """Keep one grading of the student's revision. A submission is refused
        (`AssignmentClosed`) after the due date or once the attempts are used."""
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> SubmissionSummary:
            assignment = _by_id(conn, enrolment.assignment_id)
            if kind is GradeKind.SUBMIT:
                if assignment.due is not None and now > assignment.due:
                    raise AssignmentClosed(
                        f"“{assignment.title}” was due {to_text(assignment.due)[:16]} UTC;"
                        " submissions are closed"
                    )
                used = _count(conn, enrolment, GradeKind.SUBMIT)
                if assignment.attempts is not None and used >= assignment.attempts:
                    raise AssignmentClosed(
                        f"every attempt is used ({used} of {assignment.attempts});"
                        " ask your instructor"
                    )
            cursor = conn.execute(
                "INSERT INTO submissions (assignment_id, user_id, kind, workspace_id,"
                " revision, at, passed, score, preflight, report, fingerprint)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    enrolment.assignment_id,
                    enrolment.user_id,
                    kind.value,
                    enrolment.workspace_id,
                    revision,
                    to_text(now),
                    int(passed),
                    float(score),
                    None if preflight is None else int(preflight),
                    json.dumps(dict(report)),
                    fingerprint,
                ),
            )
            row = conn.execute(
                f"SELECT {_GRADED} FROM submissions WHERE id = ?", (cursor.lastrowid,)
            ).fetchone()
            return _summary(row)

        return self.db.write(write)

    def history(self, enrolment: Enrolment) -> list[SubmissionSummary]:
        """The student's checks and submissions, newest first."""
        rows = self.db.read(
            lambda c: c.execute(
                f"SELECT {_GRADED} FROM submissions WHERE assignment_id = ? AND user_id = ?"
                " ORDER BY id DESC",
                (enrolment.assignment_id, enrolment.user_id),
            ).fetchall()
        )
        return [_summary(r) for r in rows]

    def submission(self, assignment_id: int, submission_id: int) -> Submission:
        row = self.db.read(
            lambda c: c.execute(
                f"SELECT {_GRADED}, u.username FROM submissions AS s JOIN users AS u"
                " ON u.id = s.user_id WHERE s.assignment_id = ? AND s.id = ?",
                (assignment_id, submission_id),
            ).fetchone()
        )
        if row is None:
            raise NotFound(f"no check or submission {submission_id} of assignment {assignment_id}")
        return Submission(
            _summary(row), row["assignment_id"], row["username"], row["workspace_id"],
            json.loads(row["report"]),
        )  # fmt: skip

    def attempts_left(self, enrolment: Enrolment) -> int | None:
        assignment = self.get(enrolment.assignment_id)
        if assignment.attempts is None:
            return None
        used = self.db.read(lambda c: _count(c, enrolment, GradeKind.SUBMIT))
        return max(0, assignment.attempts - used)

    # --- the class view -------------------------------------------------------------------

    def class_rows(self, assignment_id: int) -> list[ClassRow]:
        """One row per student the assignment was handed to (enabled students of the class
        or its group), by username."""

        def read(conn: sqlite3.Connection) -> list[ClassRow]:
            assignment = _by_id(conn, assignment_id)
            students = conn.execute(
                "SELECT u.id, u.username, u.display_name, g.name AS group_name"
                " FROM users AS u LEFT JOIN groups AS g ON g.id = u.group_id"
                " WHERE u.role = 'student' AND u.disabled = 0"
                " AND (? IS NULL OR g.name = ?) ORDER BY u.username",
                (assignment.group, assignment.group),
            ).fetchall()
            return [_class_row(conn, assignment, s) for s in students]

        return self.db.read(read)


def _by_id(conn: sqlite3.Connection, assignment_id: int) -> Assignment:
    row = conn.execute(_SELECT + " WHERE a.id = ?", (assignment_id,)).fetchone()
    if row is None:
        raise NotFound(f"no assignment {assignment_id}")
    return _assignment(row)


def _count(conn: sqlite3.Connection, enrolment: Enrolment, kind: GradeKind) -> int:
    return int(
        conn.execute(
            "SELECT count(*) FROM submissions WHERE assignment_id = ? AND user_id = ? AND kind = ?",
            (enrolment.assignment_id, enrolment.user_id, kind.value),
        ).fetchone()[0]
    )


def _class_row(conn: sqlite3.Connection, assignment: Assignment, student: sqlite3.Row) -> ClassRow:
    where = "FROM submissions WHERE assignment_id = ? AND user_id = ?"
    key = (assignment.id, student["id"])
    enrolled = conn.execute(
        _ENROLMENT + " WHERE s.assignment_id = ? AND s.user_id = ?", key
    ).fetchone()
    enrolment = None if enrolled is None else _enrolment(enrolled)
    latest = conn.execute(f"SELECT {_GRADED} {where} ORDER BY id DESC LIMIT 1", key).fetchone()
    best = conn.execute(
        f"SELECT {_GRADED} {where} AND kind = 'submit' ORDER BY score DESC, id LIMIT 1", key
    ).fetchone()
    counts = dict(conn.execute(f"SELECT kind, count(*) {where} GROUP BY kind", key).fetchall())
    first_pass = conn.execute(f"SELECT min(at) {where} AND passed = 1", key).fetchone()[0]
    prints = conn.execute(
        f"SELECT DISTINCT fingerprint {where} AND fingerprint IS NOT NULL ORDER BY 1", key
    ).fetchall()
    last_saved = None
    if enrolment is not None:
        last_saved = conn.execute(
            "SELECT max(created) FROM revisions WHERE workspace_id = ?",
            (enrolment.workspace_id,),
        ).fetchone()[0]
    submitted = int(counts.get(GradeKind.SUBMIT.value, 0))
    return ClassRow(
        username=student["username"],
        display_name=student["display_name"],
        group=student["group_name"],
        enrolment=enrolment,
        latest_check=None if latest is None else _summary(latest),
        best=None if best is None else _summary(best),
        checks=int(counts.get(GradeKind.CHECK.value, 0)),
        submissions=submitted,
        attempts_left=None
        if assignment.attempts is None
        else max(0, assignment.attempts - submitted),
        last_saved=from_text_or_none(last_saved),
        first_pass=from_text_or_none(first_pass),
        fingerprints=tuple(r[0] for r in prints),
    )
