"""What grading says: a `Report` per submission, one `CheckResult` per check.

Pydantic records, so the CLI's JSON, the server's responses and the IDE read one shape
(`Report.model_dump(mode="json")`). `line` is the line of the student's program that
caused a failure, where there is one. The text and CSV forms are here too, so the command
and the instructor's CSV export say the same.
"""

from __future__ import annotations

import csv
import re
from collections.abc import Sequence

from pydantic import BaseModel, ConfigDict

from melfa.grade.model import CheckKind


class CheckResult(BaseModel):
    model_config = ConfigDict(frozen=True)

    kind: CheckKind
    title: str  # what was checked, in the instructor's or the default words
    passed: bool
    message: str  # why it failed (or what was found when it passed)
    line: int | None = None  # the line of the program that caused a failure
    weight: float = 1.0
    not_run: bool = False  # not judged: the program could not be simulated (message: why)


class Report(BaseModel):
    model_config = ConfigDict(frozen=True)

    passed: bool  # every check passed
    score: float  # the weights of the checks that passed
    max_score: float  # the weights of every check
    checks: tuple[CheckResult, ...]
    variant: str | None = None  # the seed graded against (None: as written)
    cycle_time: float | None = None  # simulated seconds, when the run reached END

    @classmethod
    def of(
        cls, checks: Sequence[CheckResult], variant: str | None, cycle_time: float | None
    ) -> Report:
        score = sum(c.weight for c in checks if c.passed)
        total = sum(c.weight for c in checks)
        return cls(
            passed=all(c.passed for c in checks),
            score=score,
            max_score=total,
            checks=tuple(checks),
            variant=variant,
            cycle_time=cycle_time,
        )


NOT_RUN = "not run: "
"""How the message of a check that was not judged begins (the reason follows)."""


def report_text(report: Report, name: str) -> str:
    """A submission's report as the terminal shows it: one check a line, failures with
    their line and why; the checks the simulator could not judge in one line with the
    reason once (not once per check, nor again when a failure above already says it)."""
    head = "passed" if report.passed else "failed"
    cycle = f", cycle {report.cycle_time:.1f} s" if report.cycle_time is not None else ""
    out = [f"{name}: {head}, score {report.score:g} of {report.max_score:g}{cycle}"]
    said: list[str] = []
    not_run: dict[str, list[str]] = {}
    for c in report.checks:
        if c.not_run:
            not_run.setdefault(c.message.removeprefix(NOT_RUN), []).append(c.title)
        elif c.passed:
            out.append(f"  ok    {c.title}")
        else:
            said.append(c.message)
            out.append(f"  FAIL  {c.title}{_where(c)}: {c.message}")
    for why, titles in not_run.items():
        count = f"{len(titles)} check{'' if len(titles) == 1 else 's'}"
        if any(why in message for message in said):
            reason = "until the error above is fixed"
        else:
            reason = f"as the program could not run ({why})"
        out.append(f"  NOT RUN  {count}, {reason}: {'; '.join(titles)}")
    return "\n".join(out) + "\n"


def _where(c: CheckResult) -> str:
    """The failure's line, " (line 18)", unless its message already names that line."""
    if c.line is None or re.search(rf"\bline {c.line}\b", c.message):
        return ""
    return f" (line {c.line})"


CSV_COLUMNS = ("submission", "variant", "passed", "score", "max_score", "failed", "first_line")


def reports_csv(rows: Sequence[tuple[str, Report]]) -> str:
    """One row per submission: name, variant, passed, score, the failed checks' titles and
    the first line a failed check points at (for a spreadsheet or an LMS)."""
    out = _Text()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for name, r in rows:
        failed = [c for c in r.checks if not c.passed]
        lines = [c.line for c in failed if c.line is not None]
        writer.writerow(
            [
                name,
                r.variant or "",
                "yes" if r.passed else "no",
                f"{r.score:g}",
                f"{r.max_score:g}",
                "; ".join(c.title for c in failed),
                min(lines) if lines else "",
            ]
        )
    return "".join(out)


class _Text(list[str]):
    """What `csv.writer` writes to, kept in memory (the package does no I/O)."""

    def write(self, text: str) -> int:
        self.append(text)
        return len(text)
