"""``melfa grade ASSIGNMENT_DIR SUBMISSION.MB4 [SUBMISSION.POS] …``: grade programs against
an assignment on the simulated RV-6S, for an instructor's terminal, an LMS or CI.

Thin: the files are read here, the grading is `melfa.grade` (docs/assignments.md). Each
program is graded with the points file that follows it. Several submissions are graded in
worker processes (``--jobs``; the simulator is CPU-bound). Exit 0 when every submission was
graded, passed or not; 2 for a broken assignment or a submission that cannot be read.
"""

from __future__ import annotations

import enum
import json
import os
import sys
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import typer

from melfa.cli.checking import FileKind, UsageError, read_text_file
from melfa.cli.typer_app import app
from melfa.grade import (
    Assignment,
    AssignmentError,
    Report,
    Submission,
    grade,
    load_assignment,
    read_folder,
    report_text,
    reports_csv,
)


class OutputFormat(enum.StrEnum):
    TEXT = "text"
    JSON = "json"
    CSV = "csv"


@dataclass(frozen=True, slots=True)
class Named:
    """A submission and the name it is reported under (its program's path)."""

    name: str
    submission: Submission


def submissions_of(paths: Sequence[Path]) -> list[Named]:
    """Programs, each with the points file right after it (UsageError: what and where)."""
    out: list[Named] = []
    for path in paths:
        kind = FileKind.POINTS if path.suffix.upper() == ".POS" else FileKind.PROGRAM
        text = read_text_file(path, kind).text
        if kind is FileKind.POINTS:
            if not out or out[-1].submission.points is not None:
                raise UsageError(f"{path}: a points file follows the program it belongs to")
            last = out.pop()
            out.append(Named(last.name, Submission(last.submission.program, text)))
        else:
            out.append(Named(str(path), Submission(text)))
    return out


_assignment: Assignment | None = None


def _init(assignment: Assignment) -> None:
    global _assignment
    _assignment = assignment


def _grade_one(item: tuple[Submission, str | None]) -> Report:
    assert _assignment is not None
    return grade(_assignment, item[0], item[1])


def grade_all(
    assignment: Assignment,
    items: Sequence[tuple[Submission, str | None]],
    jobs: int = 1,
) -> list[Report]:
    """Each (submission, variant seed)'s report, in order; in `jobs` worker processes when
    more than one."""
    if jobs <= 1 or len(items) <= 1:
        return [grade(assignment, s, variant) for s, variant in items]
    workers = min(jobs, len(items))
    with ProcessPoolExecutor(workers, initializer=_init, initargs=(assignment,)) as pool:
        return list(pool.map(_grade_one, items, chunksize=max(1, len(items) // (workers * 4))))


def _fail(message: str) -> typer.Exit:
    sys.stderr.write(f"error: {message}\n")
    return typer.Exit(2)


@app.command("grade")
def grade_command(
    assignment_dir: Annotated[
        Path,
        typer.Argument(metavar="ASSIGNMENT_DIR", help="The assignment folder (assignment.toml)."),
    ],
    files: Annotated[
        list[Path],
        typer.Argument(
            metavar="SUBMISSION.MB4 [SUBMISSION.POS] …",
            help="Programs to grade, each followed by its points file if it has one.",
        ),
    ],
    output: Annotated[
        OutputFormat,
        typer.Option("--format", help="text, json (one object per submission) or csv."),
    ] = OutputFormat.TEXT,
    variant: Annotated[
        str | None,
        typer.Option("--variant", metavar="SEED", help="Grade against this seed's variant."),
    ] = None,
    jobs: Annotated[
        int,
        typer.Option("--jobs", min=1, help="Worker processes for several submissions."),
    ] = os.cpu_count() or 1,
) -> None:
    """Grade programs against an assignment on the simulated RV-6S (docs/assignments.md).

    Exit 0 when every submission was graded (passed or not), 2 for a broken assignment or
    a submission that cannot be read.
    """
    try:
        assignment = load_assignment(read_folder(assignment_dir))
    except AssignmentError as exc:
        raise _fail(f"the assignment {assignment_dir} is broken:\n{exc}") from None
    try:
        named = submissions_of(files)
    except UsageError as exc:
        raise _fail(str(exc)) from None
    reports = grade_all(assignment, [(n.submission, variant) for n in named], jobs)
    rows = [(n.name, r) for n, r in zip(named, reports, strict=True)]
    if output is OutputFormat.JSON:
        data = [{"submission": name, **r.model_dump(mode="json")} for name, r in rows]
        sys.stdout.write(json.dumps(data, indent=2, ensure_ascii=False) + "\n")
    elif output is OutputFormat.CSV:
        sys.stdout.write(reports_csv(rows))
    else:
        sys.stdout.write("\n".join(report_text(r, name) for name, r in rows))
