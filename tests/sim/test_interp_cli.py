"""`run_and_trace`: the no-robot trace behind ``melfa sim --run``."""

from __future__ import annotations

import io
from pathlib import Path

from melfa.sim.interp.cli_trace import run_and_trace

PROGRAM = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"
POINTS = (
    "DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)\n"
    "DEF POS Pb=(225.48,-363.55,683.37,-128.32,2.12,-123.50)(7,0)\n"
)


def write(tmp_path: Path, program: str, points: str | None = None) -> tuple[Path, Path | None]:
    prog = tmp_path / "TEST.MB4"
    prog.write_text(program)
    pts = None
    if points is not None:
        pts = tmp_path / "TEST.POS"
        pts.write_text(points)
    return prog, pts


def test_trace_shows_each_step_with_pose_and_hand(tmp_path: Path) -> None:
    prog, pts = write(tmp_path, PROGRAM, POINTS)
    out = io.StringIO()
    assert run_and_trace(prog, pts, True, out) == 0
    lines = out.getvalue().splitlines()
    rows = [ln.split() for ln in lines[1:] if ln.split()[1].isdigit()]
    assert [r[1] for r in rows[:7]] == ["10", "20", "30", "40", "50", "60", "70"]
    mov_pb = next(r for r in rows if r[1] == "50")
    assert mov_pb[4:7] == ["584.73", "141.04", "385.25"]  # MOV Pb starts where Pa was
    assert lines[-2].split()[-1] == "O---"  # hand 1 open at the end
    assert lines[-1].startswith("finished at line 70")


def test_run_time_error_gives_line_message_and_exit_1(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, PROGRAM)  # no points: Pa has no value
    out = io.StringIO()
    assert run_and_trace(prog, None, True, out) == 1
    assert out.getvalue().splitlines()[-1].endswith("L3700 in line 40: variable PA has no value")


def test_missing_file_and_broken_points_exit_2(tmp_path: Path) -> None:
    out = io.StringIO()
    assert run_and_trace(tmp_path / "NOPE.MB4", None, True, out) == 2
    assert "cannot read" in out.getvalue()
    prog, pts = write(tmp_path, PROGRAM, "DEF POS Pa=(1,2)(7,0)\n")
    out = io.StringIO()
    assert run_and_trace(prog, pts, True, out) == 2
    assert "TEST.POS:1:" in out.getvalue()


def test_endless_program_is_cut_at_max_time(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, "10 DLY 1\n20 GOTO 10\n")
    out = io.StringIO()
    assert run_and_trace(prog, None, True, out, max_time=5) == 0
    assert out.getvalue().splitlines()[-1].startswith("still running at line")
