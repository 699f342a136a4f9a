"""`run_and_trace`: the no-robot trace behind ``melfa sim --run``."""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import pytest

from melfa.sim.interp.cli_trace import STATEMENT_WIDTH, run_and_trace
from melfa.sim.interp.interpreter import STEP_TIME_S
from melfa.sim.interp.start import RunStart

PROGRAM = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"
POINTS = (
    "DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)\n"
    "DEF POS Pb=(225.48,-363.55,683.37,-128.32,2.12,-123.50)(7,0)\n"
)
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@dataclass
class Row:
    start: float
    took: float
    line: int
    statement: str
    pose: list[float]
    hands: str


def rows(text: str) -> list[Row]:
    """The step rows of a trace, read by column."""
    out = []
    for ln in text.splitlines():
        cells = ln[: 25 + STATEMENT_WIDTH]
        if len(ln) < 25 + STATEMENT_WIDTH or not cells[:9].strip().replace(".", "").isdigit():
            continue
        rest = ln[25 + STATEMENT_WIDTH :].split()
        out.append(
            Row(
                start=float(cells[:9]),
                took=float(cells[10:17]) if cells[10:17].strip() else 0.0,
                line=int(cells[18:23]),
                statement=cells[25:].rstrip(),
                pose=[float(v) for v in rest[:6]],
                hands=rest[6],
            )
        )
    return out


def write(tmp_path: Path, program: str, points: str | None = None) -> tuple[Path, Path | None]:
    prog = tmp_path / "TEST.MB4"
    prog.write_text(program)
    pts = None
    if points is not None:
        pts = tmp_path / "TEST.POS"
        pts.write_text(points)
    return prog, pts


def trace(prog: Path, pts: Path | None, **kwargs: object) -> tuple[int, str]:
    out = io.StringIO()
    code = run_and_trace(prog, pts, True, out, **kwargs)  # type: ignore[arg-type]
    return code, out.getvalue()


def test_each_row_is_a_step_after_it_ran(tmp_path: Path) -> None:
    code, text = trace(*write(tmp_path, PROGRAM, POINTS))
    assert code == 0
    got = rows(text)
    assert [r.line for r in got] == [10, 20, 30, 40, 50, 60, 70]
    mov_pa, mov_pb, hopen = got[3], got[4], got[5]
    assert mov_pa.pose[:3] == [584.73, 141.04, 385.25]  # where MOV Pa left the tool
    assert mov_pa.took > 0 and mov_pb.start == pytest.approx(mov_pa.start + mov_pa.took, abs=2e-3)
    assert (mov_pa.hands, hopen.hands) == ("----", "O---")
    assert got[0].took == pytest.approx(STEP_TIME_S, abs=1e-3)  # SERVO ON: one step time


def test_summary_gives_simulated_time_final_pose_and_hands(tmp_path: Path) -> None:
    _, text = trace(*write(tmp_path, PROGRAM, POINTS))
    last = text.splitlines()[-1]
    end = rows(text)[-1].start
    assert last.startswith(f"finished at line 70 after {end:.3f} s (simulated)")
    assert "X 225.48 Y -363.55 Z 683.37 mm, A -128.32 B 2.12 C -123.50 °, (7,0)" in last
    assert last.endswith("hand 1 open")


def test_header_names_the_units() -> None:
    code, text = trace(EXAMPLES / "sample.MB4", EXAMPLES / "sample.POS")
    assert code == 0
    header = next(ln for ln in text.splitlines() if "statement" in ln)
    assert "x mm" in header and "a °" in header and "took s" in header


def test_comments_are_left_out_and_long_statements_cut(tmp_path: Path) -> None:
    program = "10 M1 = 54   ' the diameter\n20 M2 = M1 + M1 + M1 + M1 + M1 + M1 + M1 + M1\n"
    _, text = trace(*write(tmp_path, program))
    first, second = rows(text)
    assert first.statement == "M1 = 54"
    assert len(second.statement) == STATEMENT_WIDTH and second.statement.endswith("…")


def test_print_output_appears_under_its_step(tmp_path: Path) -> None:
    _, text = trace(*write(tmp_path, '10 M1 = 6 * 7\n20 PRINT "M1 is", M1\n30 END\n'))
    lines = text.splitlines()
    at = next(i for i, ln in enumerate(lines) if "PRINT " in ln and "PRINT>" not in ln)
    assert lines[at + 1].strip() == "PRINT> M1 is,42"


def test_pyramid_example_ends_home_with_the_hand_open() -> None:
    code, text = trace(EXAMPLES / "pyramid.MB4", EXAMPLES / "pyramid.POS")
    assert code == 0
    last = text.splitlines()[-1]
    assert last.startswith("finished at line 27 after")
    assert "X 400.00 Y 0.00 Z 645.00 mm" in last and last.endswith("hand 1 open")
    closes = [r for r in rows(text) if r.statement == "HCLOSE 1"]
    assert len(closes) == 6  # six pieces picked


def test_run_time_error_gives_line_source_number_and_message(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, PROGRAM)  # no points: Pa has no value
    code, text = trace(prog, None)
    assert code == 1
    lines = text.splitlines()
    # three steps ran before line 40 (SERVO ON, OVRD, SPD)
    assert lines[-3].startswith(f"stopped by an error at line 40 after {3 * STEP_TIME_S:.3f} s")
    assert lines[-2] == (
        f"{prog}:4: error in line 40: L3700 Undefined (uninitialised) variable "
        "(variable PA has no value)"
    )
    assert lines[-1] == "    40 MOV Pa"


def test_joint_limit_error_is_h_level_with_the_controller_text(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, "SERVO ON\nJ1 = (175,0,90,0,90,0)\nMOV J1\n")
    code, text = trace(prog, None)
    assert code == 1
    assert "error in line 3: H2160 Joint angle exceeds the limit" in text
    assert text.splitlines()[-1] == "    MOV J1"


def test_inputs_release_a_wait(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, "10 WAIT M_IN(3) = 1\n20 HOPEN 1\n30 END\n")
    code, text = trace(prog, None, max_time=5)
    assert code == 0
    assert text.splitlines()[-1].startswith("waiting (WAIT) at line 10, stopped after 5 s")
    code, text = trace(prog, None, max_time=5, inputs={3: 1})
    assert code == 0
    assert text.splitlines()[-1].startswith("finished at line 30")


def test_missing_file_and_broken_points_exit_2(tmp_path: Path) -> None:
    code, text = trace(tmp_path / "NOPE.MB4", None)
    assert code == 2 and "cannot read" in text
    prog, pts = write(tmp_path, PROGRAM, "DEF POS Pa=(1,2)(7,0)\n")
    code, text = trace(prog, pts)
    assert code == 2 and "TEST.POS:1:" in text


def test_endless_program_is_cut_at_max_time(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, "10 DLY 1\n20 GOTO 10\n")
    code, text = trace(prog, None, max_time=5)
    assert code == 0
    assert text.splitlines()[-1].startswith("still running at line")


def test_hlt_pauses(tmp_path: Path) -> None:
    prog, _ = write(tmp_path, "10 M1 = 1\n20 HLT\n30 END\n")
    code, text = trace(prog, None)
    assert code == 0
    assert text.splitlines()[-1].startswith("paused by HLT at line 20")


def test_a_run_can_start_with_the_servo_on_elsewhere_and_with_input_lines(
    tmp_path: Path,
) -> None:
    program = '10 MOV P1\n20 OPEN "COM1:" AS #1\n30 INPUT #1, M1\n40 HOPEN 1\n50 END\n'
    prog, pts = write(tmp_path, program, "P1=(400,0,600,180,0,180)(7,0)\n")
    code, text = trace(prog, pts)
    assert code == 1 and "L2000" in text  # the simulator's default: servo off
    start = RunStart.parse(True, "0,10,90,0,80,0", ["1=42"])
    code, text = trace(prog, pts, start=start)
    assert code == 0, text
    first = rows(text)[0]
    assert first.line == 10 and first.start == 0.0
    assert text.splitlines()[-1].startswith("finished at line 50")
    with pytest.raises(ValueError, match="--joints"):
        RunStart.parse(False, "1,2", None)
    with pytest.raises(ValueError, match="--feed"):
        RunStart.parse(False, None, ["x=1"])


def test_a_run_can_start_at_a_pose_in_xyz(tmp_path: Path) -> None:
    """--pose is solved to joints by melfa.kin: the run starts (and, with nothing to do,
    ends) with the arm's flange where the pose says, under its flags."""
    prog, _ = write(tmp_path, "10 DLY 0.1\n20 END\n")
    for given in ("300,100,500,180,0,180", "(+300.00,+100.00,+500.00,+180.00,+0.00,+180.00)(7,0)"):
        code, text = trace(prog, None, start=RunStart.parse(True, None, None, given))
        assert code == 0, text
        assert "X 300.00 Y 100.00 Z 500.00 mm, A 180.00 B 0.00 C 180.00 °, (7,0)" in text


def test_a_start_the_arm_cannot_take_is_refused_with_why() -> None:
    with pytest.raises(
        ValueError,
        match=r"^--pose 2000,0,500,180,0,180: the start position is "
        r"out of the RV-6S's reach \(its wrist centre is \d+ mm from the shoulder",
    ):
        RunStart.parse(False, None, None, "2000,0,500,180,0,180")
    with pytest.raises(ValueError, match=r"reachable only with flags \(7,0\), not \(6,0\)"):
        RunStart.parse(False, None, None, "400,0,645,180,0,180,6,0")
    with pytest.raises(
        ValueError,
        match=r"^--joints 0,140,90,0,90,0: the start position has "
        "J2 = 140°, beyond its limit",
    ):
        RunStart.parse(False, "0,140,90,0,90,0", None)
    with pytest.raises(ValueError, match=r"^--pose '1,2' is not a position X,Y,Z,A,B,C"):
        RunStart.parse(False, None, None, "1,2")
    with pytest.raises(ValueError, match="give one"):
        RunStart.parse(False, "0,0,90,0,90,0", None, "400,0,645,180,0,180")


def test_points_are_read_with_the_programs_def_pos(tmp_path: Path) -> None:
    # get_box is a position only because the program says DEF POS GET_BOX.
    program = "10 DEF POS GET_BOX\n20 MOV get_box\n30 END\n"
    prog, pts = write(tmp_path, program, "get_box=(400,0,600,180,0,180)(7,0)\n")
    code, text = trace(prog, pts, start=RunStart(servo_on=True))
    assert code == 0, text
    assert "X 400.00 Y 0.00 Z 600.00 mm" in text.splitlines()[-1]
