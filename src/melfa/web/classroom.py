"""The glue between the store's assignments and the grading engine (`melfa.grade`), for
`web.routes.assignments`: reading a folder (files or a zip), a student's starter and cell,
grading a revision, the class view's filters and its CSV. The engine and the store do the
work; nothing here decides who may do what (`store.assignment_access` does)."""

from __future__ import annotations

import csv
import io
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

from markdown_it import MarkdownIt

from melfa.grade import Assignment as GradedAssignment
from melfa.grade import (
    AssignmentError,
    CheckKind,
    Report,
    Submission,
    grade,
    load_assignment,
    variant_cell,
    variant_points,
)
from melfa.grade.engine import default_title
from melfa.lang.encoding import decode_text
from melfa.lang.plan import plan_upload
from melfa.store import Assignment, ClassRow, Enrolment, SubmissionSummary
from melfa.store.runs import RunInfo
from melfa.vocab.classroom import (
    COLUMN_WORDS,
    RESULT_WORDS,
    STUCK_AFTER_MIN,
    ClassColumn,
    ClassFilter,
    summary_words,
)
from melfa.web.assignment_models import (
    AssignmentCheckOut,
    AssignmentInfo,
    ClassRowOut,
    FolderOut,
    GradingOut,
    MineOut,
    Problem,
)
from melfa.web.errors import ApiError
from melfa.web.targets import LAB

MAX_ZIP_BYTES = 4 * 1024 * 1024
MAX_FOLDER_FILES = 32

_markdown = MarkdownIt("commonmark", {"html": False})


def statement_html(markdown: str) -> str:
    """The statement as HTML: CommonMark with raw HTML escaped (nothing a student's browser
    would run), links only of the kinds markdown-it allows."""
    return str(_markdown.render(markdown))


# --- folders --------------------------------------------------------------------------------


def unzip(data: bytes) -> dict[str, str]:
    """The text files of a zipped assignment folder, by their path inside the folder (one
    top-level directory, as a zipped folder has, is dropped)."""
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
    except zipfile.BadZipFile:
        raise ApiError(
            422, "invalid-assignment", "not a zip file: choose the folder's .zip"
        ) from None
    with archive:
        infos = [i for i in archive.infolist() if not i.is_dir()]
        infos = [i for i in infos if not _hidden(i.filename)]
        if len(infos) > MAX_FOLDER_FILES:
            raise ApiError(
                422, "invalid-assignment", f"the zip holds more than {MAX_FOLDER_FILES} files"
            )
        if sum(i.file_size for i in infos) > MAX_ZIP_BYTES:
            raise ApiError(413, "too-large", "an assignment folder holds at most 4 MiB")
        names = [i.filename for i in infos]
        tops = {n.split("/", 1)[0] for n in names}
        strip = len(tops) == 1 and all("/" in n for n in names)
        files: dict[str, str] = {}
        for info in infos:
            name = info.filename.split("/", 1)[1] if strip else info.filename
            files[name] = decode_text(archive.read(info))
    return files


def _hidden(name: str) -> bool:
    return any(part.startswith(".") or part == "__MACOSX" for part in name.split("/"))


def stem(title: str) -> str:
    """A file name made of the assignment's title ("Pyramid of 6" → "Pyramid-of-6")."""
    kept = "".join(c if c.isascii() and (c.isalnum() or c in "-_") else "-" for c in title)
    return "-".join(p for p in kept.split("-") if p) or "assignment"


def zipped(title: str, files: Mapping[str, str]) -> bytes:
    """The folder as a zip with one top-level directory named after the assignment."""
    top = stem(title)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, text in sorted(files.items()):
            archive.writestr(f"{top}/{name}", text)
    return out.getvalue()


def load(files: Mapping[str, str]) -> GradedAssignment:
    """The engine's assignment, or 422 ``invalid-assignment`` listing every problem."""
    try:
        return load_assignment(files)
    except AssignmentError as exc:
        raise ApiError(
            422,
            "invalid-assignment",
            f"the assignment folder has {len(exc.problems)} problem(s): {exc.problems[0]}",
            detail={"problems": [_problem(p) for p in exc.problems]},
        ) from None


def _problem(p: Any) -> dict[str, str]:
    return {"file": p.file, "where": p.where, "message": p.message}


def checks_of(assignment: GradedAssignment) -> list[AssignmentCheckOut]:
    return [
        AssignmentCheckOut(kind=CheckKind(c.kind), title=c.title or default_title(c))
        for c in assignment.spec.checks
    ]


def folder_out(files: Mapping[str, str]) -> FolderOut:
    """A folder read for the publish form: what it holds, or what is wrong with it."""
    try:
        a = load_assignment(files)
    except AssignmentError as exc:
        return FolderOut(
            files=dict(files), title=None, statement_html=None, checks=[], variants=[],
            due=None, attempts=None, problems=[Problem(**_problem(p)) for p in exc.problems],
        )  # fmt: skip
    return FolderOut(
        files=dict(files),
        title=a.title,
        statement_html=statement_html(a.statement),
        checks=checks_of(a),
        variants=sorted(a.spec.variants),
        due=due_of(a),
        attempts=a.spec.attempts,
        problems=[],
    )


def due_of(a: GradedAssignment) -> datetime | None:
    """The assignment.toml's due time (a date alone: the end of that day, UTC)."""
    due = a.spec.due
    if due is None:
        return None
    if isinstance(due, datetime):
        return due if due.tzinfo is not None else due.replace(tzinfo=UTC)
    return datetime(due.year, due.month, due.day, 23, 59, 59, tzinfo=UTC)


# --- a student's copy -----------------------------------------------------------------------


def starter(a: GradedAssignment, seed: int) -> tuple[str, str]:
    """The starter program and the points of seed `seed`'s variant (0: as written)."""
    v = a.variant(seed or None)
    return a.starter or "", variant_points(a, v) or ""


SEED_TRIES = 1000


def fresh_seed(a: GradedAssignment, taken: list[int]) -> int:
    """A seed for the next student: the first after those taken whose positions differ
    from every taken seed's, while the variants have such a one left (then simply the
    next). The engine picks a variant from a seed at random, so two consecutive seeds
    may share one; two students next to each other should not."""
    start = max(taken, default=0) + 1
    used = {_offsets(a, s) for s in taken}
    for seed in range(start, start + SEED_TRIES):
        if _offsets(a, seed) not in used:
            return seed
    return start


def _offsets(a: GradedAssignment, seed: int) -> tuple[tuple[str, tuple[float, ...]], ...]:
    return tuple(sorted((k, tuple(v)) for k, v in a.variant(seed).offsets.items()))


def variant_words(a: GradedAssignment, seed: int) -> str:
    words = a.variant(seed or None).describe()
    return RESULT_WORDS["variant"].format(words=words) if words else ""


def cell_of(a: GradedAssignment, seed: int) -> dict[str, Any]:
    return variant_cell(a, a.variant(seed or None)).to_json()


@dataclass(frozen=True, slots=True)
class Graded:
    """A text graded: the engine's report, whether it passed pre-flight (its no-collision
    check, when the assignment has one) and its fingerprint as the lab robot loads it."""

    report: Report
    preflight: bool | None
    fingerprint: str


def graded(a: GradedAssignment, seed: int, program: str, points: str) -> Graded:
    report = grade(a, Submission(program, points), variant=seed or None)
    flight = [c.passed for c in report.checks if c.kind is CheckKind.NO_COLLISION]
    fingerprint = plan_upload(program, points).fingerprint
    return Graded(report, all(flight) if flight else None, fingerprint)


def ran_on_arm(row: ClassRow, runs: list[RunInfo]) -> int:
    """How many of the student's recorded runs on the lab robot, since they opened the
    assignment, ran a text of theirs that was graded."""
    if row.enrolment is None:
        return 0
    graded_prints = set(row.fingerprints)
    return sum(
        1
        for r in runs
        if r.target == LAB and r.started >= row.enrolment.opened and r.fingerprint in graded_prints
    )


# --- records out ----------------------------------------------------------------------------


def grading_out(s: SubmissionSummary) -> GradingOut:
    return GradingOut(
        id=s.id, kind=s.kind, revision=s.revision, at=s.at, passed=s.passed, score=s.score,
        max_score=s.max_score, preflight=s.preflight, checks_passed=s.checks_passed,
        checks=s.checks,
        summary=summary_words(s.passed, s.checks_passed, s.checks, s.score, s.max_score),
    )  # fmt: skip


def _maybe(s: SubmissionSummary | None) -> GradingOut | None:
    return None if s is None else grading_out(s)


def mine_out(
    a: GradedAssignment,
    copy: Enrolment,
    attempts_left: int | None,
    history: list[SubmissionSummary],
) -> MineOut:
    submitted = [h for h in history if h.kind.value == "submit"]
    best = max(submitted, key=lambda h: (h.score, -h.id), default=None)
    return MineOut(
        workspace_id=copy.workspace_id,
        seed=copy.seed,
        variant=variant_words(a, copy.seed),
        opened=copy.opened,
        attempts_left=attempts_left,
        latest=_maybe(history[0] if history else None),
        best=_maybe(best),
    )


def info_out(assignment: Assignment, mine: MineOut | None = None) -> AssignmentInfo:
    return AssignmentInfo(
        id=assignment.id,
        title=assignment.title,
        group=assignment.group,
        variants=assignment.variants,
        due=assignment.due,
        attempts=assignment.attempts,
        author=assignment.author,
        created=assignment.created,
        mine=mine,
    )


def stuck(row: ClassRow, now: datetime) -> bool:
    """Opened at least `STUCK_AFTER_MIN` minutes ago, and nothing has passed yet."""
    if row.enrolment is None or row.first_pass is not None:
        return False
    return now - row.enrolment.opened >= timedelta(minutes=STUCK_AFTER_MIN)


def matches(row: ClassRow, which: ClassFilter, now: datetime) -> bool:
    match which:
        case ClassFilter.ALL:
            return True
        case ClassFilter.STUCK:
            return stuck(row, now)
        case ClassFilter.NOT_OPENED:
            return row.enrolment is None
        case ClassFilter.NOT_SUBMITTED:
            return row.enrolment is not None and row.submissions == 0
        case ClassFilter.PASSED:
            return row.best is not None and row.best.passed


def row_out(row: ClassRow, now: datetime, ran: int) -> ClassRowOut:
    e = row.enrolment
    return ClassRowOut(
        student=row.username,
        display_name=row.display_name,
        group=row.group,
        seed=None if e is None else e.seed,
        workspace_id=None if e is None else e.workspace_id,
        opened=None if e is None else e.opened,
        latest=_maybe(row.latest_check),
        best=_maybe(row.best),
        checks=row.checks,
        submissions=row.submissions,
        attempts_left=row.attempts_left,
        last_saved=row.last_saved,
        first_pass=row.first_pass,
        stuck=stuck(row, now),
        ran_on_arm=ran,
    )


def _result(g: GradingOut | None, opened: bool) -> str:
    if g is None:
        return RESULT_WORDS["none" if opened else "not-opened"]
    return g.summary


def class_csv(rows: list[ClassRowOut]) -> str:
    """The class view as CSV: the same columns, in the same words, as on screen."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\r\n")
    writer.writerow([COLUMN_WORDS[c] for c in ClassColumn])
    for r in rows:
        opened = r.opened is not None
        flight = r.latest.preflight if r.latest is not None else None
        cells = {
            ClassColumn.STUDENT: r.student,
            ClassColumn.GROUP: r.group or "",
            ClassColumn.VARIANT: "" if r.seed is None else r.seed,
            ClassColumn.LATEST: _result(r.latest, opened),
            ClassColumn.BEST: "" if r.best is None else _result(r.best, opened),
            ClassColumn.ATTEMPTS: r.submissions
            if r.attempts_left is None
            else f"{r.submissions} ({r.attempts_left} left)",
            ClassColumn.LAST_SAVED: "" if r.last_saved is None else r.last_saved.isoformat(),
            ClassColumn.PREFLIGHT: RESULT_WORDS[
                "unknown" if flight is None else "preflight-ok" if flight else "preflight-failed"
            ],
            ClassColumn.RAN: r.ran_on_arm,
        }
        writer.writerow([cells[c] for c in ClassColumn])
    return out.getvalue()


__all__ = [
    "Graded",
    "cell_of",
    "checks_of",
    "class_csv",
    "due_of",
    "folder_out",
    "fresh_seed",
    "graded",
    "grading_out",
    "info_out",
    "load",
    "matches",
    "mine_out",
    "ran_on_arm",
    "row_out",
    "starter",
    "statement_html",
    "stem",
    "stuck",
    "unzip",
    "variant_words",
    "zipped",
]
