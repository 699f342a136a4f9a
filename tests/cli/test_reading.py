"""One text reader for every command that takes a program: encodings, binary files refused,
the same extension rules (issue 25: `debug` and `sim --run` read UTF-16 as garbage and ran
binary files; `upload` took a .POS or a .txt as the program)."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli.typer_app import app

runner = CliRunner()
PROGRAM = "10 M1 = 6 * 7\r\n20 PRINT M1\r\n30 END\r\n"


def invoke(*args: str, stdin: str = "") -> tuple[int, str]:
    result = runner.invoke(app, list(args), input=stdin)
    return result.exit_code, result.output


def test_a_utf16_program_runs_in_sim_and_debug(tmp_path: Path) -> None:
    prog = tmp_path / "NOTEPAD.MB4"
    prog.write_bytes(PROGRAM.encode("utf-16"))  # Windows Notepad's "Unicode", with a BOM
    code, out = invoke("sim", "--run", str(prog), "--fast")
    assert code == 0 and "PRINT> 42" in out and out.splitlines()[-1].startswith("finished")
    code, out = invoke("debug", str(prog), stdin="run\nprint M1\nquit\n")
    assert (code, out.splitlines()[-1]) == (0, "42")


@pytest.mark.parametrize("command", [["sim", "--run"], ["debug"], ["upload"]])
def test_a_binary_file_is_refused_by_every_command(tmp_path: Path, command: list[str]) -> None:
    prog = tmp_path / "SYSORG.MB4"
    prog.write_bytes(b"ROBPRG\x00\x00\x00\x11!\x00\x02")  # the controller's own binary form
    code, out = (
        invoke(*command, str(prog), "--robot", "sim")
        if command == ["upload"]
        else (invoke(*command, str(prog)))
    )
    assert code == 2
    assert "This is not a text file (a NUL byte at line 1, column 7)" in " ".join(out.split())


@pytest.mark.parametrize("command", [["sim", "--run"], ["debug"], ["upload"]])
def test_a_points_file_or_a_txt_is_not_taken_as_the_program(
    tmp_path: Path, command: list[str]
) -> None:
    extra = ["--robot", "sim"] if command == ["upload"] else []
    pos = tmp_path / "cell.POS"
    pos.write_text("P1=(400,0,600,180,0,180)(7,0)\n")
    code, out = invoke(*command, str(pos), *extra)
    assert code == 2 and "this is a points file (give it with --points)" in " ".join(out.split())
    txt = tmp_path / "prog.txt"
    txt.write_text(PROGRAM)
    code, out = invoke(*command, str(txt), *extra)
    assert code == 2 and "unknown file type (.txt)" in out
