"""A broken assignment is reported with what and where (file, table, key); variants."""

from __future__ import annotations

import json

import pytest

from melfa.grade import AssignmentError, Submission, grade, load_assignment, variant_points
from melfa.grade.model import FinalPose

HEAD = 'title = "T"\nstatement = "s.md"\n'
OK_CHECK = '[[checks]]\nkind = "no-errors"\n'


def problems(toml: str, **files: str) -> list[str]:
    with pytest.raises(AssignmentError) as caught:
        load_assignment({"assignment.toml": toml, "s.md": "# T", **files})
    return [str(p) for p in caught.value.problems]


def test_a_good_assignment_loads() -> None:
    a = load_assignment({"assignment.toml": HEAD + OK_CHECK, "s.md": "# T\nBuild it."})
    assert a.title == "T" and a.statement == "# T\nBuild it." and a.cell.floor_z == 0.0


def test_not_toml_says_where() -> None:
    (p,) = problems(HEAD + "[[checks]\n")
    assert p.startswith("assignment.toml: not TOML") and "line 3" in p


def test_a_missing_manifest() -> None:
    with pytest.raises(AssignmentError, match=r"assignment\.toml: missing"):
        load_assignment({"s.md": "x"})


def test_an_unknown_kind_names_the_table() -> None:
    (p,) = problems(HEAD + OK_CHECK + '[[checks]]\nkind = "final-pos"\n')
    assert p.startswith("assignment.toml: [[checks]] 2: kind 'final-pos' is not a check")
    assert "final-pose" in p
    (p,) = problems(HEAD + "[[checks]]\nmax_s = 3\n")
    assert p.startswith("assignment.toml: [[checks]] 1: kind is missing")


def test_a_wrong_or_missing_key_names_table_and_key() -> None:
    found = problems(
        HEAD
        + '[[checks]]\nkind = "part-at"\npart = "block"\nposition = [1, 2]\n'
        + '[[checks]]\nkind = "cycle-time"\n'
        + '[[checks]]\nkind = "final-pose"\npose = [1, 2, 3]\ntolerance = 3\n'
    )
    assert "assignment.toml: [[checks]] 1 (kind = 'part-at'), position.2: is missing" in found
    assert "assignment.toml: [[checks]] 2 (kind = 'cycle-time'), max_s: is missing" in found
    assert (
        "assignment.toml: [[checks]] 3 (kind = 'final-pose'), tolerance: "
        "is not a key of this table" in found
    )


def test_a_pose_of_the_wrong_length() -> None:
    (p,) = problems(HEAD + '[[checks]]\nkind = "final-pose"\npose = [1, 2, 3, 4]\n')
    assert p == (
        "assignment.toml: [[checks]] 1 (kind = 'final-pose'), pose: "
        "a pose is [x, y, z] or [x, y, z, a, b, c] (mm, degrees)"
    )


def test_top_level_keys() -> None:
    found = problems('statement = "s.md"\nattempts = 0\n' + OK_CHECK)
    assert "assignment.toml: title: is missing" in found
    assert any(p.startswith("assignment.toml: attempts: ") for p in found)
    (p,) = problems(HEAD)
    assert p.startswith("assignment.toml: checks: ")


def test_files_it_names_must_be_in_the_folder() -> None:
    found = problems(
        HEAD.replace("s.md", "statement.md")
        + 'starter = "../etc/passwd"\ncell = "c.json"\n'
        + OK_CHECK
    )
    assert "assignment.toml: statement: names 'statement.md', which is not in the folder" in found
    assert "assignment.toml: starter: '../etc/passwd' must be a file in the folder" in found
    assert "assignment.toml: cell: names 'c.json', which is not in the folder" in found


def test_a_broken_cell_names_its_file() -> None:
    (p,) = problems(HEAD + 'cell = "c.json"\n' + OK_CHECK, **{"c.json": '{"floor_z": "low"}'})
    assert p.startswith("c.json: floor_z must be a number")


def test_names_a_check_uses_must_exist() -> None:
    found = problems(
        HEAD
        + '[[checks]]\nkind = "uses"\nstatements = ["GOSUB", "GOSBU"]\n'
        + '[[checks]]\nkind = "final-pose"\npose = [1, 2, 3]\nfollows = "pick"\n'
        + '[[checks]]\nkind = "part-at"\npart = "block 9"\nposition = [1, 2, 3]\n'
    )
    assert (
        "assignment.toml: [[checks]] 1 (kind = 'uses'), statements: "
        "'GOSBU' is not a MELFA BASIC IV statement" in found
    )
    assert (
        "assignment.toml: [[checks]] 2 (kind = 'final-pose'), follows: "
        "no variant group 'pick' (none)" in found
    )
    assert any(
        p.startswith("assignment.toml: [[checks]] 3 (kind = 'part-at'), part: no part 'block 9'")
        for p in found
    )


def test_a_broken_variant_group() -> None:
    found = problems(
        HEAD
        + OK_CHECK
        + '[variants.pick]\noffsets = [[0, 0, 0]]\ndx = [-10, 10]\npoints = ["Pa"]\n'
    )
    assert "assignment.toml: [variants.pick]: give offsets or dx/dy/dz ranges, not both" in found


VARIANTS = (
    HEAD
    + 'starter_points = "s.POS"\n'
    + '[[checks]]\nkind = "final-pose"\npose = [400, 0, 450]\nfollows = "place"\n'
    + "[variants.place]\noffsets = [[0, 0, 0], [0, 40, 0], [0, -40, 0], [20, 0, 0]]\n"
    + 'points = ["P1"]\n'
)
STARTER = "' where it goes\nDEF POS P1=(400,0,450,180,0,180)(7,0)\n"


def test_a_seed_picks_the_same_variant_every_time_and_the_checks_follow_it() -> None:
    a = load_assignment({"assignment.toml": VARIANTS, "s.md": "#", "s.POS": STARTER})
    offsets = {seed: a.variant(seed).offset("place") for seed in range(12)}
    assert offsets == {seed: a.variant(str(seed)).offset("place") for seed in range(12)}
    assert len(set(offsets.values())) > 1  # the class gets different places
    seed = next(s for s, o in offsets.items() if o != (0.0, 0.0, 0.0))
    dx, dy, dz = offsets[seed]
    # the starter points the student gets are moved; the comment stays
    moved = variant_points(a, a.variant(seed))
    assert moved is not None and moved.startswith("' where it goes\n")
    assert f"({400 + dx:.2f},{dy:.2f},{450 + dz:.2f}," in moved
    # a program that goes to the point passes for its own variant, not for the plain one
    program = "SERVO ON\nMOV P1\nEND\n"
    mine = grade(a, Submission(program, moved), seed)
    assert mine.passed and mine.variant == str(seed)
    assert not grade(a, Submission(program, STARTER), seed).passed
    assert grade(a, Submission(program, STARTER)).passed
    # without points of its own a submission is run with its variant's starter points
    assert grade(a, Submission(program), seed).passed


def test_ranges_stay_within_their_bounds_on_their_steps() -> None:
    toml = HEAD + OK_CHECK + "[variants.pick]\ndx = [-20, 20]\ndy = [0, 30]\nstep_mm = 10\n"
    a = load_assignment({"assignment.toml": toml, "s.md": "#"})
    seen = {a.variant(f"student-{i}").offset("pick") for i in range(40)}
    assert all(
        dx in (-20, -10, 0, 10, 20) and dy in (0, 10, 20, 30) and dz == 0 for dx, dy, dz in seen
    )
    assert len(seen) > 5
    assert a.variant(None).offset("pick") == (0.0, 0.0, 0.0)


def test_the_check_models_are_the_format() -> None:
    assert set(FinalPose.model_fields) == {
        "kind", "title", "weight", "pose", "tolerance_mm", "tolerance_deg", "follows",
    }  # fmt: skip
    json.dumps(FinalPose.model_json_schema())


def test_an_unknown_top_level_key_or_group_key() -> None:
    found = problems(HEAD + "deadline = 2026-12-01\n" + OK_CHECK + "[variants.g]\nshift = 3\n")
    assert "assignment.toml: deadline: is not a key of this table" in found
    assert "assignment.toml: [variants.g], shift: is not a key of this table" in found
