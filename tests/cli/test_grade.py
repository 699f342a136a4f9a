"""`melfa grade`: every check kind through the command, its three formats, exit codes, a
broken assignment and a submission that does not parse (graded, never a traceback)."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from tests.grade import sample

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "assignments"
SOLUTIONS = EXAMPLES / "pyramid-solutions"

# The grading tests' program (tests.grade.sample), setting the puck down at P3 on the
# other stand.
PROGRAM = sample.PROGRAM.replace("RETURN\n", "MVS P3\nHOPEN 1\nRETURN\n")
POINTS = sample.POINTS + "DEF POS P3=(400,-100,400,180,0,180)(7,0)\n"

# One check of every kind; the program above passes each.
EVERY_KIND = """title = "Every kind"
statement = "statement.md"
cell = "cell.json"

[[checks]]
kind = "final-pose"
pose = [400, -100, 400, 180, 0, 180]

[[checks]]
kind = "visits"
poses = [[400, 0, 450], [400, 100, 400]]
in_order = true

[[checks]]
kind = "part-at"
part = "puck"
position = [400, -100, 290]
tolerance_mm = 1

[[checks]]
kind = "hand"
action = "close"
at = [[400, 100, 400]]

[[checks]]
kind = "hand"
action = "open"
at = [[400, -100, 400]]
title = "sets the puck on the other stand"

[[checks]]
kind = "no-collision"

[[checks]]
kind = "cycle-time"
max_s = 30

[[checks]]
kind = "io"
inputs = {8 = 1}
outputs = {10 = 1}

[[checks]]
kind = "uses"
statements = ["GOSUB", "MVS"]

[[checks]]
kind = "avoids"
statements = ["GOTO"]

[[checks]]
kind = "no-errors"
"""
# A puck on a stand, its centre at the grip point (100 mm below the flange) when the
# flange is at P2, and a second stand under P3.
CELL = {
    "floor_z": 0,
    "gripper": {"hand": 1, "grip": 100, "tolerance": 5, "length": 60, "radius": 10},
    "fixtures": [{"name": "stand", "shape": "box", "size": [40, 40, 290],
                  "position": [400, 100, 0]},
                 {"name": "other", "shape": "box", "size": [40, 40, 290],
                  "position": [400, -100, 0]}],
    "parts": [{"name": "puck", "shape": "cylinder", "diameter": 20, "height": 20,
               "position": [400, 100, 290]}],
}  # fmt: skip


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    a = tmp_path / "every-kind"
    a.mkdir()
    (a / "assignment.toml").write_text(EVERY_KIND)
    (a / "statement.md").write_text("# Every kind\n")
    (a / "cell.json").write_text(json.dumps(CELL))
    return a


def write(tmp_path: Path, name: str, text: str | bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return path


def run(*args: str | Path) -> tuple[int, str, str]:
    result = CliRunner().invoke(app, ["grade", *map(str, args)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.stdout, result.stderr


def as_json(*args: str | Path) -> list[dict[str, object]]:
    code, out, err = run(*args, "--format", "json", "--jobs", "1")
    assert code == 0, err
    data = json.loads(out)
    assert isinstance(data, list)
    return data


def by_kind(obj: dict[str, object]) -> dict[str, tuple[bool, int | None, str]]:
    checks = obj["checks"]
    assert isinstance(checks, list)
    return {
        c.get("title") if c["kind"] == "hand" else c["kind"]: (c["passed"], c["line"], c["message"])
        for c in checks
    }


def test_every_kind_passes_on_a_program_that_does_it(folder: Path, tmp_path: Path) -> None:
    prog, pts = write(tmp_path, "good.MB4", PROGRAM), write(tmp_path, "good.POS", POINTS)
    (report,) = as_json(folder, prog, pts)
    assert report["submission"] == str(prog)
    failed = {k: v for k, v in by_kind(report).items() if not v[0]}
    assert report["passed"] is True and not failed, failed
    assert report["score"] == report["max_score"] == 11


def test_every_kind_fails_with_its_line_on_a_program_that_does_not(
    folder: Path, tmp_path: Path
) -> None:
    wrong = (
        PROGRAM.replace("MVS P2\n", "MVS P2, -30\n", 1)  # closes 30 mm above the puck
        .replace("M_OUT(10) = M_IN(8)", "M_OUT(10) = 0")
        .replace("GOSUB *UP", "GOTO *UP")
        .replace("MVS P3", "SPD 1\nMVS P3")  # 1 mm/s: the cycle takes minutes
        .replace("RETURN", "END")
    )
    prog, pts = write(tmp_path, "bad.MB4", wrong), write(tmp_path, "bad.POS", POINTS)
    (report,) = as_json(folder, prog, pts)
    got = by_kind(report)
    assert report["passed"] is False
    assert got["final-pose"][:2] == (True, None)  # it still ends at P3
    assert got["visits"][:2] == (False, 4)  # nearest to P2: 30 mm above it, line 4
    assert (
        got["part-at"][:2] == (False, None)
        and "puck never moved from (400, 100, 290)" in got["part-at"][2]
    )
    closes = got["hand 1 closes at 1 place"]
    assert closes[:2] == (False, 5) and "closed at (400, 100, 430) and took nothing" in closes[2]
    opens = got["sets the puck on the other stand"]
    assert opens[:2] == (False, 12) and "but the hand does not open there" in opens[2]
    assert got["cycle-time"][:2] == (False, 12) and "more than 30 s" in got["cycle-time"][2]
    assert got["io"][:2] == (False, 6) and "M_OUT(10) is 0, expected 1" in got["io"][2]
    assert got["uses"] == (False, None, "the program does not use GOSUB")
    assert got["avoids"][:2] == (False, 7)
    assert got["no-collision"][0] is True and got["no-errors"][0] is True

    # In words: a failure's line once ("line 7 uses GOTO", not "(line 7): line 7 uses …").
    code, out, _ = run(folder, prog, pts, "--jobs", "1")
    assert code == 0
    (avoids,) = [x for x in out.splitlines() if "uses GOTO" in x]
    assert avoids.count("line 7") == 1, avoids
    assert "(line 4): " in out  # a message that does not name its line still gets it


def test_a_collision_and_a_checker_error(folder: Path, tmp_path: Path) -> None:
    low = POINTS.replace("(400,100,400,", "(400,100,-20,")
    (report,) = as_json(
        folder, write(tmp_path, "low.MB4", PROGRAM), write(tmp_path, "low.POS", low)
    )
    assert by_kind(report)["no-collision"][:2] == (False, 4)
    typo = PROGRAM.replace("HCLOSE 1", "HCLOSE 1,,")
    (report,) = as_json(folder, write(tmp_path, "typo.MB4", typo), write(tmp_path, "t.POS", POINTS))
    assert by_kind(report)["no-errors"][:2] == (False, 5)


def test_a_submission_that_does_not_parse_is_graded_as_failed(folder: Path, tmp_path: Path) -> None:
    garbage = write(tmp_path, "garbage.MB4", "SERVO ON\nWIHLE M1 < 3\nMOV P1 +* (\n")
    code, out, err = run(folder, garbage, "--jobs", "1")
    assert code == 0 and not err
    assert "Traceback" not in out
    assert "garbage.MB4: failed, score 1 of 11" in out  # avoids GOTO is judged on the tree
    # The checker's error is said once, and the checks it kept from running in one line.
    lines = out.splitlines()
    error = [x for x in lines if "FAIL  no errors from melfa check" in x]
    assert len(error) == 1 and error[0].count("line 2") == 1, out
    (skipped,) = [x for x in lines if "NOT RUN" in x]
    assert skipped.startswith("  NOT RUN  8 checks, until the error above is fixed: the tool ends")
    assert "WIHLE" not in skipped and "not run: line 2" not in out
    assert sum("WIHLE" in x for x in lines) == 1
    (report,) = as_json(folder, garbage)
    assert report["passed"] is False
    assert all(c["line"] == 2 for c in report["checks"] if not c["passed"] and c["kind"] != "uses")
    assert "did you mean WHILE?" in by_kind(report)["no-errors"][2]


def test_a_broken_assignment_is_exit_2_with_what_and_where(folder: Path, tmp_path: Path) -> None:
    prog = write(tmp_path, "p.MB4", PROGRAM)
    toml = folder / "assignment.toml"
    toml.write_text(EVERY_KIND.replace("max_s = 30", 'max_s = "soon"').replace('"puck"', '"pack"'))
    code, out, err = run(folder, prog)
    assert code == 2 and not out and "Traceback" not in err
    assert f"error: the assignment {folder} is broken:" in err
    assert "assignment.toml: [[checks]] 7 (kind = 'cycle-time'), max_s: " in err
    toml.write_text(EVERY_KIND.replace('part = "puck"', 'part = "pack"'))
    code, _, err = run(folder, prog)
    assert code == 2 and "[[checks]] 3 (kind = 'part-at'), part: no part 'pack' (puck)" in err
    (folder / "cell.json").write_text("{")
    code, _, err = run(folder, prog)
    assert code == 2 and "cell.json: not JSON" in err
    code, _, err = run(tmp_path / "nowhere", prog)
    assert code == 2 and "is not a folder" in err


def test_an_unreadable_submission_is_exit_2(folder: Path, tmp_path: Path) -> None:
    code, out, err = run(folder, tmp_path / "missing.MB4")
    assert code == 2 and not out and "missing.MB4: no such file" in err
    code, _, err = run(folder, write(tmp_path, "bin.MB4", b"\x00\x01\x02ROBOT"))
    assert code == 2 and "not a text file" in err
    code, _, err = run(folder, write(tmp_path, "only.POS", POINTS))
    assert code == 2 and "a points file follows the program it belongs to" in err


def test_the_pyramid_example_in_csv_with_worker_processes() -> None:
    ref, pts = SOLUTIONS / "reference.MB4", SOLUTIONS / "reference.POS"
    high, goto = SOLUTIONS / "wrong" / "high.MB4", SOLUTIONS / "wrong" / "goto.MB4"
    code, out, err = run(
        EXAMPLES / "pyramid", ref, pts, high, pts, goto, pts, "--format", "csv", "--jobs", "2"
    )
    assert code == 0, err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [(r["submission"], r["passed"], r["score"], r["max_score"]) for r in rows] == [
        (str(ref), "yes", "15", "15"),
        (str(high), "no", "14", "15"),
        (str(goto), "no", "13", "15"),
    ]
    assert (
        rows[1]["failed"] == "sets each block down on its place" and rows[1]["first_line"] == "47"
    )
    assert rows[2]["first_line"] == "18"


def test_a_variant_moves_the_checks(folder: Path, tmp_path: Path) -> None:
    toml = folder / "assignment.toml"
    toml.write_text(
        EVERY_KIND.replace(
            "pose = [400, -100, 400, 180, 0, 180]", 'pose = [400, -100, 400]\nfollows = "g"'
        )
        + "[variants.g]\noffsets = [[0, 0, 0], [0, 0, 30]]\n"
    )
    prog, pts = write(tmp_path, "p.MB4", PROGRAM), write(tmp_path, "p.POS", POINTS)
    results = {}
    for seed in map(str, range(4)):
        (report,) = as_json(folder, prog, pts, "--variant", seed)
        assert report["variant"] == seed
        results[seed] = by_kind(report)["final-pose"][0]
    assert set(results.values()) == {True, False}  # some seeds move the place 30 mm up
