"""Assignments in a real SQLite file: publishing, each student's copy (seed, workspace with
the starter of their variant), checks and submissions (attempts, due date), the class view's
rows, and who may do what (`assignment_access`, the one place)."""

from __future__ import annotations

from datetime import timedelta

import pytest

from melfa.store import (
    AccessDenied,
    AssignmentAction,
    AssignmentClosed,
    GradeKind,
    InvalidValue,
    NotFound,
    Store,
    User,
    allowed,
    require,
)
from tests.store.conftest import FakeClock

FILES = {"assignment.toml": 'title = "Pyramid"\nstatement = "Stack them."\n'}


def _people(store: Store) -> tuple[User, User, User, User]:
    teacher = store.accounts.create_user("tess", "teacher-password", role="instructor")
    ann = store.accounts.create_user("ann", "ann-password-1", group="G1")
    bob = store.accounts.create_user("bob", "bob-password-1", group="G2")
    cid = store.accounts.create_user("cid", "cid-password-1")
    return teacher, ann, bob, cid


def _starter(seed: int) -> tuple[str, str]:
    return (f"' variant {seed}\nMOV P1\nEND\n", f"P1=(400,{seed * 10},300,180,0,180)(7,0)\n")


def test_students_get_their_own_seed_and_a_workspace_with_their_variant(store: Store) -> None:
    teacher, ann, bob, _ = _people(store)
    made = store.assignments.publish(teacher, "Pyramid", FILES, variants=True, attempts=2)
    assert (made.title, made.group, made.files) == ("Pyramid", None, FILES)

    a = store.assignments.open(made.id, ann, _starter)
    b = store.assignments.open(made.id, bob, _starter)
    assert (a.seed, b.seed) == (1, 2)
    assert store.assignments.open(made.id, ann, _starter) == a  # made once
    state = store.workspaces.state(a.workspace_id)
    assert (state.workspace.name, state.workspace.owner) == ("Pyramid", "ann")
    assert state.program == "' variant 1\nMOV P1\nEND\n"
    assert store.workspaces.state(b.workspace_id).points.startswith("P1=(400,20,")
    assert store.assignments.enrolments(ann) == {made.id: a}


def test_without_variants_everybody_has_seed_0_and_a_free_name(store: Store) -> None:
    teacher, ann, _, _ = _people(store)
    store.workspaces.create(ann, "Pyramid")  # a name she already uses
    made = store.assignments.publish(teacher, "Pyramid", FILES)
    copy = store.assignments.open(made.id, ann, _starter)
    assert copy.seed == 0
    assert store.workspaces.get(copy.workspace_id).name == "Pyramid (2)"


def test_submissions_count_against_attempts_and_the_due_date(
    store: Store, clock: FakeClock
) -> None:
    teacher, ann, _, _ = _people(store)
    due = clock.now + timedelta(hours=1)
    made = store.assignments.publish(teacher, "Pyramid", FILES, attempts=2, due=due)
    copy = store.assignments.open(made.id, ann, _starter)

    def grade(kind: GradeKind, passed: bool, score: float) -> None:
        store.assignments.record(
            copy, kind, 1, passed=passed, score=score, preflight=True, report={"passed": passed}
        )

    for _ in range(3):
        grade(GradeKind.CHECK, False, 0.5)  # checks are never limited
    grade(GradeKind.SUBMIT, False, 0.5)
    assert store.assignments.attempts_left(copy) == 1
    grade(GradeKind.SUBMIT, True, 1.0)
    with pytest.raises(AssignmentClosed, match="every attempt is used"):
        grade(GradeKind.SUBMIT, True, 1.0)
    assert store.assignments.attempts_left(copy) == 0

    later = store.assignments.publish(teacher, "Late", FILES, due=due)
    late_copy = store.assignments.open(later.id, ann, _starter)
    clock.advance(hours=2)
    with pytest.raises(AssignmentClosed, match="submissions are closed"):
        store.assignments.record(
            late_copy, GradeKind.SUBMIT, 1, passed=True, score=1, preflight=None, report={}
        )
    history = store.assignments.history(copy)
    assert [h.kind for h in history] == [GradeKind.SUBMIT] * 2 + [GradeKind.CHECK] * 3
    full = store.assignments.submission(made.id, history[0].id)
    assert (full.username, full.report, full.summary.passed) == ("ann", {"passed": True}, True)


def test_class_rows_list_every_student_it_was_handed_to(store: Store, clock: FakeClock) -> None:
    teacher, ann, _, _ = _people(store)
    for_g1 = store.assignments.publish(teacher, "G1 only", FILES, group="G1")
    assert [r.username for r in store.assignments.class_rows(for_g1.id)] == ["ann"]

    made = store.assignments.publish(teacher, "Pyramid", FILES, attempts=3)
    copy = store.assignments.open(made.id, ann, _starter)
    store.assignments.record(
        copy, GradeKind.CHECK, 1, passed=False, score=0.25, preflight=False, report={}
    )
    clock.advance(minutes=5)
    store.assignments.record(
        copy, GradeKind.SUBMIT, 1, passed=True, score=1.0, preflight=True, report={}
    )
    store.assignments.record(
        copy, GradeKind.SUBMIT, 1, passed=False, score=0.5, preflight=True, report={}
    )
    rows = {r.username: r for r in store.assignments.class_rows(made.id)}
    assert list(rows) == ["ann", "bob", "cid"]  # staff are not students
    row = rows["ann"]
    assert row.enrolment == copy
    assert row.latest_check is not None and row.latest_check.score == 0.5
    assert row.best is not None and (row.best.score, row.best.passed) == (1.0, True)
    assert (row.checks, row.submissions, row.attempts_left) == (1, 2, 1)
    assert row.first_pass == clock.now
    assert row.last_saved is not None
    assert rows["bob"].enrolment is None and rows["bob"].latest_check is None


def test_who_may_do_what_is_decided_in_one_place(store: Store) -> None:
    teacher, ann, bob, _ = _people(store)
    for_g1 = store.assignments.publish(teacher, "G1 only", FILES, group="G1")
    assert allowed(ann, AssignmentAction.WORK, for_g1)
    assert not allowed(bob, AssignmentAction.VIEW, for_g1)
    assert not allowed(ann, AssignmentAction.MANAGE, for_g1)
    assert allowed(teacher, AssignmentAction.MANAGE, for_g1)
    with pytest.raises(AccessDenied, match="only instructors"):
        require(ann, AssignmentAction.MANAGE, for_g1)
    disabled = store.accounts.set_disabled("ann", True)
    assert not allowed(disabled, AssignmentAction.VIEW, for_g1)


def test_unknown_assignment_group_or_empty_folder_is_refused(store: Store) -> None:
    teacher, *_ = _people(store)
    with pytest.raises(NotFound):
        store.assignments.get(99)
    with pytest.raises(NotFound, match="no group"):
        store.assignments.publish(teacher, "X", FILES, group="nobody")
    with pytest.raises(InvalidValue, match=r"at least its assignment\.toml"):
        store.assignments.publish(teacher, "X", {})
