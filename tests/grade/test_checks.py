"""Every kind of check, passing and failing on a small program, each failure on its line."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.grade import Report, Submission, grade, load_assignment
from melfa.grade.model import CheckKind
from tests.grade.sample import POINTS, PROGRAM


def assignment(checks: str, cell: dict[str, object] | None = None, extra: str = "") -> object:
    toml = f'title = "Test"\nstatement = "s.md"\n{extra}\n{checks}'
    files: dict[str, str] = {"assignment.toml": toml, "s.md": "# Test\n"}
    if cell is not None:
        files["cell.json"] = json.dumps(cell)
        files["assignment.toml"] = 'cell = "cell.json"\n' + toml
    return load_assignment(files)


def only(report: Report) -> tuple[bool, str, int | None]:
    (check,) = report.checks
    return check.passed, check.message, check.line


def run(checks: str, program: str = PROGRAM, **kw: object) -> tuple[bool, str, int | None]:
    return only(grade(assignment(checks, **kw), Submission(program, POINTS)))  # type: ignore[arg-type]


def test_final_pose_passes_where_the_tool_ends_and_fails_on_the_last_move() -> None:
    # MVS P2, -50: 50 mm up (the tool points down)
    ok = run('[[checks]]\nkind = "final-pose"\npose = [400, 100, 450, 180, 0, 180]')
    assert ok[0], ok
    passed, message, line = run('[[checks]]\nkind = "final-pose"\npose = [400, 100, 400]')
    assert not passed and line == 10
    assert "50.0 mm from (400, 100, 400)" in message


def test_final_pose_checks_the_orientation_when_given() -> None:
    passed, message, line = run(
        '[[checks]]\nkind = "final-pose"\npose = [400, 100, 450, 180, 0, 90]\ntolerance_deg = 2'
    )
    assert not passed and line == 10 and "turned 90.0°" in message


def test_visits_in_order_and_out_of_order() -> None:
    poses = "poses = [[400, 0, 450], [400, 100, 400]]"
    assert run(f'[[checks]]\nkind = "visits"\n{poses}\nin_order = true')[0]
    back = "poses = [[400, 100, 400], [400, 0, 450]]"
    passed, message, _ = run(f'[[checks]]\nkind = "visits"\n{back}\nin_order = true')
    assert not passed and "after the poses before it" in message
    assert run(f'[[checks]]\nkind = "visits"\n{back}')[0]  # any order


def test_visits_fails_on_the_move_that_came_nearest() -> None:
    passed, message, line = run('[[checks]]\nkind = "visits"\nposes = [[400, 100, 380]]')
    assert not passed and line == 4 and "20.0 mm away" in message


def test_no_collision_fails_on_the_move_into_an_obstacle() -> None:
    checks = '[[checks]]\nkind = "no-collision"'
    assert run(checks)[0]
    cell = {"floor_z": 0, "boxes": [{"name": "jig", "min": [380, 80, 380], "max": [420, 120, 420]}]}
    passed, message, line = run(checks, cell=cell)
    assert not passed and line == 4 and "'jig'" in message


def test_no_collision_fails_on_a_run_error() -> None:
    program = PROGRAM.replace("MVS P2\n", "MVS P2\nM1 = 1 / 0\n")
    passed, message, line = run('[[checks]]\nkind = "no-collision"', program)
    assert not passed and line == 5 and "L" in message


def test_cycle_time_fails_on_the_move_the_time_runs_out_in() -> None:
    report = grade(
        assignment('[[checks]]\nkind = "cycle-time"\nmax_s = 60'),  # type: ignore[arg-type]
        Submission(PROGRAM, POINTS),
    )
    assert report.passed and report.cycle_time is not None
    cycle = report.cycle_time
    passed, message, line = run(f'[[checks]]\nkind = "cycle-time"\nmax_s = {cycle * 0.7:.3f}')
    assert not passed and line in (2, 4, 10) and f"{cycle:.1f} s" in message


def test_cycle_time_fails_when_the_run_never_ends() -> None:
    program = "SERVO ON\n*L\nMOV P1\nMOV P2\nGOTO *L\n"
    passed, message, _ = run(
        '[[checks]]\nkind = "cycle-time"\nmax_s = 60', program, extra="max_time_s = 30"
    )
    assert not passed and "does not reach END" in message


def test_io_sets_the_inputs_and_reads_the_outputs_at_the_end() -> None:
    assert run('[[checks]]\nkind = "io"\ninputs = {8 = 1}\noutputs = {10 = 1}')[0]
    passed, message, line = run('[[checks]]\nkind = "io"\noutputs = {10 = 1}')
    assert not passed and "M_OUT(10) is 0, expected 1" in message and line == 6
    passed, message, line = run('[[checks]]\nkind = "io"\noutputs = {11 = 1}')
    assert not passed and line is None and "never sets M_OUT(11)" in message


def test_uses_and_avoids_read_the_tree() -> None:
    assert run('[[checks]]\nkind = "uses"\nstatements = ["GOSUB", "mvs", "hclose"]')[0]
    passed, message, line = run('[[checks]]\nkind = "uses"\nstatements = ["FOR"]')
    assert not passed and line is None and "FOR" in message
    passed, message, line = run('[[checks]]\nkind = "avoids"\nstatements = ["GOTO", "MVS"]')
    assert not passed and line == 4 and "MVS" in message
    program = PROGRAM.replace("GOSUB *UP", "IF M_IN(8) = 1 THEN GOTO *UP")
    passed, message, line = run('[[checks]]\nkind = "avoids"\nstatements = ["GOTO"]', program)
    assert not passed and line == 7


def test_if_then_label_is_not_a_goto() -> None:
    program = PROGRAM.replace("GOSUB *UP", "IF M_IN(8) = 1 THEN *UP")
    assert run('[[checks]]\nkind = "avoids"\nstatements = ["GOTO"]', program)[0]


def test_no_errors_fails_on_the_checkers_first_error() -> None:
    assert run('[[checks]]\nkind = "no-errors"')[0]
    program = PROGRAM.replace("HOPEN 1", "HOPNE 1")
    passed, message, line = run('[[checks]]\nkind = "no-errors"', program)
    assert not passed and line == 3 and message.startswith("line 3: ")


def test_an_unparseable_submission_fails_every_run_check_with_the_checkers_message() -> None:
    a = assignment(
        '[[checks]]\nkind = "final-pose"\npose = [400, 100, 450]\n'
        '[[checks]]\nkind = "no-collision"\n[[checks]]\nkind = "avoids"\nstatements = ["GOTO"]'
    )
    report = grade(a, Submission("SERVO ON\nMOV P1\nWIHLE M1 < 3\nEND\n", POINTS))  # type: ignore[arg-type]
    assert not report.passed and report.score == 1 and report.max_score == 3
    pose, collision, avoids = report.checks
    for c in (pose, collision):
        assert not c.passed and c.not_run and c.line == 3 and "did you mean WHILE?" in c.message
    assert avoids.passed
    binary = grade(a, Submission("\x00\x01garbage(((\n", ""))  # type: ignore[arg-type]
    assert not binary.passed and all(c.line == 1 for c in binary.checks if not c.passed)


def test_score_is_the_weights_of_the_checks_that_passed() -> None:
    a = assignment(
        '[[checks]]\nkind = "uses"\nstatements = ["GOSUB"]\nweight = 3\n'
        '[[checks]]\nkind = "uses"\nstatements = ["FOR"]\ntitle = "a FOR loop"'
    )
    report = grade(a, Submission(PROGRAM, POINTS))  # type: ignore[arg-type]
    assert (report.score, report.max_score, report.passed) == (3, 4, False)
    assert [c.title for c in report.checks] == ["uses GOSUB", "a FOR loop"]
    assert [c.kind for c in report.checks] == [CheckKind.USES, CheckKind.USES]
    data = report.model_dump(mode="json")
    assert data["checks"][1] == {
        "kind": "uses",
        "title": "a FOR loop",
        "passed": False,
        "message": "the program does not use FOR",
        "line": None,
        "weight": 1.0,
        "not_run": False,
    }


@pytest.mark.parametrize("kind", [k.value for k in CheckKind])
def test_every_kind_is_documented(kind: str) -> None:
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "assignments.md").read_text()
    assert f'`kind = "{kind}"`' in doc


FRAGMENTS = [
    "SERVO ON", "MOV P1", "MVS P2", "MVS P2, -50", "HOPEN 1", "HCLOSE 1", "DLY 0.1",
    "GOSUB *UP", "GOTO *UP", "*UP", "RETURN", "END", "M1 = M1 + 1", "IF M1 > 2 THEN *UP",
    "FOR M2 = 1 TO 2", "NEXT M2", "M_OUT(10) = M_IN(8)", "WAIT M_IN(8) = 1", "MOV P9",
    "P3 = P1 + (0, 0, 2000, 0, 0, 0)", "MOV P3", "WIHLE", "MVS ,", "M1 = 1 / 0", "ERROR 9100",
    "HLT", "TOOL (0, 0, 100, 0, 0, 0)", "OVRD 200", "\x00", "' comment",
]  # fmt: skip
EVERY = assignment(
    '[[checks]]\nkind = "final-pose"\npose = [400, 0, 450]\n'
    '[[checks]]\nkind = "visits"\nposes = [[400, 100, 400]]\n'
    '[[checks]]\nkind = "hand"\naction = "open"\nat = [[400, 100, 400]]\n'
    '[[checks]]\nkind = "no-collision"\n[[checks]]\nkind = "cycle-time"\nmax_s = 5\n'
    '[[checks]]\nkind = "io"\ninputs = {8 = 1}\noutputs = {10 = 1}\n'
    '[[checks]]\nkind = "uses"\nstatements = ["GOSUB"]\n'
    '[[checks]]\nkind = "avoids"\nstatements = ["GOTO"]\n[[checks]]\nkind = "no-errors"\n',
    extra="max_time_s = 20",
)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.sampled_from(FRAGMENTS), max_size=12))
def test_any_program_is_graded_never_raises(lines: list[str]) -> None:
    """Whatever a student hands in, every check gets a result (a line within the program
    when it names one), never an exception."""
    program = "\n".join(lines) + "\n"
    report = grade(EVERY, Submission(program, POINTS))  # type: ignore[arg-type]
    assert len(report.checks) == 9
    assert report.passed == all(c.passed for c in report.checks)
    for c in report.checks:
        assert c.message
        assert c.line is None or 1 <= c.line <= max(1, len(lines)), (c, program)


def test_hand_counts_every_open_and_close_without_with_part() -> None:
    """No cell, no parts: with ``with_part = false`` each HOPEN/HCLOSE counts where it ran;
    by default a close that takes nothing is named, on its line."""
    at = "at = [[400, 100, 400]]"
    assert run(f'[[checks]]\nkind = "hand"\naction = "close"\n{at}\nwith_part = false')[0]
    opens = "at = [[400, 0, 450]]"
    assert run(f'[[checks]]\nkind = "hand"\naction = "open"\n{opens}\nwith_part = false')[0]
    passed, message, line = run(f'[[checks]]\nkind = "hand"\naction = "close"\n{at}')
    assert not passed and line == 5 and "closed at (400, 100, 400) and took nothing" in message
    far = "at = [[400, 100, 380]]"
    passed, message, line = run(
        f'[[checks]]\nkind = "hand"\naction = "close"\n{far}\nwith_part = false'
    )
    assert not passed and line == 5 and "20.0 mm from (400, 100, 380)" in message


def test_a_bug_in_the_simulator_is_a_failed_check_that_says_so(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The one stand-in here: a simulator that raises, as a bug of ours would."""
    import melfa.grade.engine as engine

    def broken(*_args: object, **_kw: object) -> None:
        raise ZeroDivisionError("a bug")

    monkeypatch.setattr(engine, "preflight", broken)
    passed, message, line = run('[[checks]]\nkind = "no-collision"')
    assert not passed and line is None
    assert message.startswith("internal error in melfa's simulator (please report it)")
