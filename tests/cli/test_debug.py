"""`melfa debug`: every console command, through the installed console script with the
commands piped to its stdin (not a terminal, so it reads them one per line)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

PROGRAM = """SERVO ON
M1 = 1
*LOOP
GOSUB *SUB
M1 = M1 + 1
IF M1 < 3 THEN GOTO *LOOP
WAIT M_IN(1) = 1
MOV P1
M9 = M8 + 1
END
*SUB
M2 = M1 * 10
RETURN
"""
POINTS = "DEF POS P1=(400.00,100.00,500.00,180.00,0.00,180.00)(7,0)\n"


def melfa() -> list[str]:
    """The installed console script (the real entry point), or `python -m melfa`."""
    script = Path(sys.executable).with_name("melfa")
    return [str(script)] if script.exists() else [sys.executable, "-m", "melfa"]


def melfa_debug(
    tmp_path: Path, commands: str, *extra: str, program: str = PROGRAM
) -> tuple[int, str, str]:
    prog = tmp_path / "prog.MB4"
    prog.write_text(program, encoding="utf-8")
    pos = tmp_path / "prog.POS"
    pos.write_text(POINTS, encoding="utf-8")
    done = subprocess.run(
        [*melfa(), "debug", str(prog), "--points", str(pos), *extra],
        input=commands,
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    return done.returncode, done.stdout, done.stderr


def test_break_run_where_step_print_finish_delete(tmp_path: Path) -> None:
    code, out, err = melfa_debug(
        tmp_path,
        "break *SUB\nbreak 5\ninfo breakpoints\nrun\nwhere\nstep\nprint M1 * 2, P1\n"
        "finish\ndelete 1\ndelete 2\ninfo breakpoints\nquit\n",
    )
    assert (code, err) == (0, "")
    lines = out.splitlines()
    assert lines[:4] == [
        "breakpoint 1 at line 11: *SUB",
        "breakpoint 2 at line 5: M1 = M1 + 1",
        "1: line 11 (*SUB): *SUB",
        "2: line 5: M1 = M1 + 1",
    ]
    assert lines[4:8] == [
        "breakpoint 1",
        "stopped at line 11: *SUB",
        "#0 line 11: *SUB",
        "#1 line 4: GOSUB *SUB",
    ]
    assert lines[8] == "stopped at line 12: M2 = M1 * 10"  # step
    assert lines[9] == "2, (+400.00,+100.00,+500.00,+180.00,+0.00,+180.00)(7,0)"
    assert lines[10:12] == ["breakpoint 2", "stopped at line 5: M1 = M1 + 1"]  # finish
    assert lines[12:] == ["deleted breakpoint 1", "deleted breakpoint 2", "no breakpoints"]


def test_next_steps_over_the_gosub_and_continue_runs_to_the_end(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(
        tmp_path,
        "break 4\nrun\nnext\nprint M2\ndelete 1\ncontinue\ninput 1=1\ncontinue\n",
        program=PROGRAM.replace("M9 = M8 + 1", "M9 = 1"),
    )
    assert code == 0
    assert "stopped at line 4: GOSUB *SUB" in out
    assert "stopped at line 5: M1 = M1 + 1\n10\n" in out  # next: the subroutine ran whole
    assert "waiting at line 7: WAIT M_IN(1) = 1" in out
    assert "M_IN(1) = 1\n" in out
    assert out.rstrip().splitlines()[-1].startswith("finished at line 10 after ")


def test_until_and_info_vars_mark_what_changed(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(tmp_path, "until 5\nstep\ninfo vars\n")
    assert code == 0
    assert "stopped at line 5: M1 = M1 + 1\nstopped at line 6:" in out
    assert "numbers:\n  M1 = 2   (changed)\n  M2 = 10\n" in out
    assert "positions:\n  P1 = (+400.00,+100.00,+500.00,+180.00,+0.00,+180.00)(7,0)\n" in out
    assert "robot:\n  P_CURR = " in out and "  M_OVRD = 100\n" in out


def test_a_run_time_error_ends_with_its_number_and_line(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(tmp_path, "run\n", "--input", "1=1")
    assert code == 1
    assert out.splitlines()[-2:] == [
        "error at line 9: L3700 Undefined (uninitialised) variable: variable M8 has no value",
        "  9 | M9 = M8 + 1",
    ]


def test_input_set_in_the_console_and_on_the_command_line(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(tmp_path, "input 1=1\nbreak 8\nrun\nprint M_IN(1)\nquit\n")
    assert code == 0
    assert "M_IN(1) = 1\n" in out
    assert "stopped at line 8: MOV P1\n1\n" in out
    _, out, _ = melfa_debug(tmp_path, "break 8\nrun\nprint M_IN(1)\n", "--input", "1=1")
    assert "stopped at line 8: MOV P1\n1\n" in out


MISTAKES = [
    ("break 99", "error: line 99 is outside the program (1..13)"),
    ("break *NOPE", "error: there is no label *NOPE in the program (labels: *LOOP, *SUB)"),
    ("delete 4", "error: there is no breakpoint 4"),
    ("print M7", "error: variable M7 has no value"),
    ("input 1=2", "error: '1=2' is not N=V (input signal number N ≥ 0, value 0 or 1)"),
    ("frobnicate", "error: unknown command 'frobnicate' (help lists the commands)"),
    ("info", "error: info what? (info vars, info breakpoints)"),
    ("speed warp", "error: 'warp' is not a speed (real, instant, or x N)"),
    ("continue", "error: the program is not running (run starts it again)"),
]


def test_mistakes_are_one_plain_line_and_the_session_goes_on(tmp_path: Path) -> None:
    script = "".join(f"{command}\nprint 1 + 1\n" for command, _ in MISTAKES[:-1])
    script += "run\ncontinue\nprint 1 + 1\n"  # finished (the error): nothing to continue
    _, out, err = melfa_debug(tmp_path, script, "--input", "1=1")
    lines = out.splitlines()
    for _, message in MISTAKES:
        assert message in lines
        assert lines[lines.index(message) + 1] == "2"  # the next command still ran
    assert "Traceback" not in out + err


def test_speed_help_and_where_before_running(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(tmp_path, "where\nspeed x4\nspeed instant\nhelp\nquit\nrun\n")
    assert code == 0
    assert out.splitlines()[:3] == [
        "the program is not running",
        "speed x4",
        "speed instant",
    ]
    assert "break N" in out and "finish" in out
    assert "stopped" not in out  # quit ended the session before run


def test_usage_errors_exit_2_and_an_unloadable_program_exits_1(tmp_path: Path) -> None:
    code, _, err = melfa_debug(tmp_path, "", "--input", "x")
    assert code == 2 and "--input 'x' is not N=V" in err
    code, _, err = melfa_debug(tmp_path, "", "--speed", "fast-ish")
    assert code == 2 and "--speed" in err
    code, _, err = melfa_debug(tmp_path, "", program="GOTO 99\n")
    assert code == 1 and "cannot run" in err and "there is no step 99" in err
    done = subprocess.run(
        [*melfa(), "debug", str(tmp_path / "missing.MB4")],
        input="",
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2 and "missing.MB4: no such file" in " ".join(done.stderr.split())


LOW = "SERVO ON\nMOV P1\nMVS P2\nMOV P1\nEND\n"
LOW_POINTS = "DEF POS P1=(500,0,100,180,0,180)(7,0)\nDEF POS P2=(500,0,-20,180,0,180)(7,0)\n"


def _low_files(tmp_path: Path) -> tuple[list[str], Path, Path]:
    prog = tmp_path / "low.MB4"
    prog.write_text(LOW, encoding="utf-8")
    pos = tmp_path / "low.POS"
    pos.write_text(LOW_POINTS, encoding="utf-8")
    return melfa(), prog, pos


def test_preflight_flags_a_move_below_the_table(tmp_path: Path) -> None:
    command, prog, pos = _low_files(tmp_path)
    done = subprocess.run(
        [*command, "debug", str(prog), "--points", str(pos), "--preflight"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "pre-flight of low.MB4 on the simulated RV-6S"
    assert lines[1].startswith("cycle time: ")
    assert "error: line 3: the move takes the tool 20.0 mm below the table" in done.stdout
    cell = tmp_path / "cell.json"
    cell.write_text('{"floor_z": -100}', encoding="utf-8")
    done = subprocess.run(
        [*command, "debug", str(prog), "--points", str(pos), "--preflight", "--cell", str(cell)],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0 and done.stdout.rstrip().endswith("0 errors, 0 warnings")
    cell.write_text('{"floor_z": "low"}', encoding="utf-8")
    done = subprocess.run(
        [*command, "debug", str(prog), "--preflight", "--cell", str(cell)],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2 and 'floor_z must be a number (mm), got "low"' in done.stderr


def test_preflight_in_the_thesis_bench_says_where_the_blocks_ended() -> None:
    examples = Path(__file__).resolve().parents[2] / "examples"
    done = subprocess.run(
        [
            *melfa(),
            "debug",
            str(examples / "pyramid.MB4"),
            "--points",
            str(examples / "pyramid.POS"),
            "--preflight",
            "--cell",
            "thesis-bench",
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    assert "where the parts ended:" in done.stdout
    assert "  block 1: (434.0, 150.0, 150.0) on block 2" in done.stdout.splitlines()
    assert done.stdout.rstrip().endswith("0 errors, 0 warnings")


def test_the_preflight_console_command(tmp_path: Path) -> None:
    code, out, _ = melfa_debug(tmp_path, "preflight\nprint 1\n", program=LOW.replace("P2", "P1"))
    assert code == 0
    assert "pre-flight of the program on the simulated RV-6S\n" in out
    assert "0 errors" in out and out.splitlines()[-1] == "1"


def test_debug_starts_with_the_servo_on_at_given_joints_and_feeds_input(tmp_path: Path) -> None:
    program = "10 MOV P1\n20 INPUT #1, M1\n30 M2 = M1 * 2\n40 END\n"
    code, out, err = melfa_debug(
        tmp_path,
        "run\nprint M2\nquit\n",
        "--servo-on",
        "--joints",
        "0,10,90,0,80,0",
        "--feed",
        "1=21",
        program=program,
    )
    assert (code, err) == (0, "")
    *_, finished, printed = out.splitlines()
    assert (finished.startswith("finished at line 4 after"), printed) == (True, "42")


def test_debug_starts_at_a_pose_and_refuses_one_out_of_reach(tmp_path: Path) -> None:
    program = "10 END\n"
    code, out, err = melfa_debug(
        tmp_path, "print P_CURR\nquit\n", "--pose", "300,100,500,180,0,180", program=program
    )
    assert (code, err) == (0, "")
    assert out.splitlines()[-1] == "(+300.00,+100.00,+500.00,+180.00,+0.00,+180.00)(7,0)"
    code, out, err = melfa_debug(
        tmp_path, "quit\n", "--pose", "2000,0,500,180,0,180", program=program
    )
    assert code == 2 and "the start position is out of the RV-6S's reach" in err
    assert "Traceback" not in err
