"""The thesis's pyramid exercise (examples/assignments/pyramid): the reference solution
passes, and each typical wrong solution fails on the check that names its mistake, with
the line that caused it."""

from __future__ import annotations

from pathlib import Path

import pytest

from melfa.grade import (
    Assignment,
    Report,
    Submission,
    grade,
    load_assignment,
    read_folder,
    variant_points,
)
from melfa.grade.model import CheckKind

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "assignments"
SOLUTIONS = EXAMPLES / "pyramid-solutions"
POINTS = (SOLUTIONS / "reference.POS").read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def pyramid() -> Assignment:
    return load_assignment(read_folder(EXAMPLES / "pyramid"))


def graded(
    assignment: Assignment, program: str, points: str = POINTS, seed: int | None = None
) -> Report:
    text = (SOLUTIONS / program).read_text(encoding="utf-8")
    return grade(assignment, Submission(text, points), seed)


def test_the_reference_solution_passes(pyramid: Assignment) -> None:
    report = graded(pyramid, "reference.MB4")
    failed = [(c.title, c.message) for c in report.checks if not c.passed]
    assert report.passed, failed
    assert report.score == report.max_score == 15
    assert report.cycle_time is not None and 90 < report.cycle_time < 120
    kinds = {c.kind for c in report.checks}
    assert {CheckKind.HAND, CheckKind.PART_AT, CheckKind.NO_COLLISION} <= kinds


WRONG = [
    # file, the check that names the mistake, the line it points at, words of its message
    ("wrong/order.MB4", "block 6 ends at (380, 150, 100)", 47, "54.0 mm from its place"),
    (
        "wrong/high.MB4",
        "sets each block down on its place",
        47,
        "10.0 mm from (380, 150, 220)",
    ),
    (
        "wrong/no-hopen.MB4",
        "sets each block down on its place",
        46,
        "at line 46, but the hand does not open there",
    ),
    ("wrong/goto.MB4", "no GOTO", 18, "line 18 uses GOTO"),
    ("wrong/goto.MB4", "picks and places in subroutines (GOSUB)", None, "does not use GOSUB"),
    ("wrong/table.MB4", "no collision, no pre-flight error", 45, "bench"),
]


@pytest.mark.parametrize(("program", "title", "line", "words"), WRONG)
def test_a_wrong_solution_fails_on_the_right_check_with_the_right_line(
    pyramid: Assignment, program: str, title: str, line: int | None, words: str
) -> None:
    report = graded(pyramid, program)
    assert not report.passed
    (check,) = [c for c in report.checks if c.title == title]
    assert not check.passed, check
    assert check.line == line, check
    assert words in check.message, check.message


def test_a_block_dropped_high_still_lands_on_its_place(pyramid: Assignment) -> None:
    """Only the hand check sees it: the block falls 10 mm onto the right place."""
    report = graded(pyramid, "wrong/high.MB4")
    failed = {c.title for c in report.checks if not c.passed}
    assert failed == {"sets each block down on its place"}


def test_the_goto_solution_builds_the_pyramid_all_the_same(pyramid: Assignment) -> None:
    report = graded(pyramid, "wrong/goto.MB4")
    assert {c.kind for c in report.checks if not c.passed} == {CheckKind.USES, CheckKind.AVOIDS}


def test_each_student_builds_with_their_own_positions(pyramid: Assignment) -> None:
    a = pyramid
    seeds = [
        s
        for s in range(40)
        if a.variant(s).offsets != {"pick": (0.0, 0.0, 0.0), "place": (0.0, 0.0, 0.0)}
    ]
    seed = seeds[0]
    mine = variant_points(a, a.variant(seed))
    assert mine is not None and mine != POINTS
    # the reference with the plain points fails this student's checks; with theirs it passes
    assert not graded(a, "reference.MB4", POINTS, seed).passed
    report = graded(a, "reference.MB4", mine, seed)
    assert report.passed, [c.message for c in report.checks if not c.passed]
    assert report.variant == str(seed)


def test_every_variant_can_be_solved(pyramid: Assignment) -> None:
    """Each of the 4 × 4 pick and place offsets a student may get: the reference solution
    with that student's starter points passes (no variant puts a block out of reach or
    into the bench)."""
    a = pyramid
    seeds: dict[object, int] = {}
    for seed in range(1, 400):
        key = tuple(sorted(a.variant(seed).offsets.items()))
        seeds.setdefault(key, seed)
    assert len(seeds) == 16
    for seed in seeds.values():
        points = variant_points(a, a.variant(seed))
        report = graded(a, "reference.MB4", points or "", seed)
        assert report.passed, (seed, [c.message for c in report.checks if not c.passed])
