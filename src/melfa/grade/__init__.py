"""Exercises that check themselves: assignments graded on the simulated RV-6S.

The API the CLI (`melfa grade`) and the server's assignments share::

    assignment = load_assignment(files)          # relative path → bytes or text
    report = grade(assignment, Submission(program, points), variant=seed)
    report.passed, report.score, [(c.kind, c.passed, c.message, c.line) for c in report.checks]

`read_folder(path)` reads an assignment folder from disk (`melfa.grade.folder`, the one
module here that touches files). docs/assignments.md describes the folder's format.
"""

from melfa.grade.assignment import Assignment, AssignmentError, Problem, load_assignment
from melfa.grade.engine import Submission, grade, variant_cell, variant_points
from melfa.grade.folder import read_folder
from melfa.grade.model import AssignmentFile, CheckKind
from melfa.grade.report import CheckResult, Report, report_text, reports_csv
from melfa.grade.variants import Variant

__all__ = [
    "Assignment",
    "AssignmentError",
    "AssignmentFile",
    "CheckKind",
    "CheckResult",
    "Problem",
    "Report",
    "Submission",
    "Variant",
    "grade",
    "load_assignment",
    "read_folder",
    "report_text",
    "reports_csv",
    "variant_cell",
    "variant_points",
]
