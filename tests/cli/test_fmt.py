"""`melfa fmt`: formats in place or elsewhere, checks, and never corrupts a program."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app

MESSY = "1 servo on\n2 ' Posició de la piràmide\n3 mov pa\n4 goto 2\n"
NUMBERED = "10 SERVO ON\n20 ' Posició de la piràmide\n30 MOV pa\n40 GOTO 20\n"


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


def fmt(runner: CliRunner, *args: str | Path) -> tuple[int, str, str]:
    result = runner.invoke(app, ["fmt", *map(str, args)])
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result.exit_code, result.stdout, result.stderr


def test_keyword_case_in_place_keeps_numbers(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(MESSY, encoding="utf-8")
    code, _, err = fmt(runner, path)
    assert code == 0
    assert path.read_text(encoding="utf-8") == (
        "1 SERVO ON\n2 ' Posició de la piràmide\n3 MOV pa\n4 GOTO 2\n"
    )
    assert "formatted" in err


def test_number_rewrites_jumps(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.mb4"
    path.write_text(MESSY, encoding="utf-8")
    assert fmt(runner, path, "--number")[0] == 0
    assert path.read_text(encoding="utf-8") == NUMBERED


def test_start_and_step(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text("servo on\nend\n", encoding="utf-8")
    assert fmt(runner, path, "--number", "--start", "100", "--step", "5")[0] == 0
    assert path.read_text(encoding="utf-8") == "100 SERVO ON\n105 END\n"
    assert fmt(runner, path, "--number", "--step", "0")[0] == 2


def test_strip_keeps_jump_targets(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(NUMBERED, encoding="utf-8")
    assert fmt(runner, path, "--strip")[0] == 0
    assert path.read_text(encoding="utf-8") == (
        "SERVO ON\n20 ' Posició de la piràmide\nMOV pa\nGOTO 20\n"
    )


def test_latin1_is_written_back_as_latin1(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "cat.MB4"
    path.write_bytes(MESSY.encode("latin-1"))
    assert fmt(runner, path, "--number")[0] == 0
    assert path.read_bytes() == NUMBERED.encode("latin-1")


def test_utf8_bom_and_crlf_are_kept(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "bom.MB4"
    path.write_bytes(b"\xef\xbb\xbf" + b"mov p1\r\nend\r\n")
    assert fmt(runner, path)[0] == 0
    assert path.read_bytes() == b"\xef\xbb\xbf" + b"MOV p1\r\nEND\r\n"


def test_check_reports_and_writes_nothing(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(MESSY, encoding="utf-8")
    code, out, err = fmt(runner, path, "--check")
    assert code == 1
    assert "would reformat" in err
    assert "-3 mov pa\n" in out and "+3 MOV pa\n" in out
    assert path.read_text(encoding="utf-8") == MESSY


def test_check_on_a_formatted_file_exits_0(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(NUMBERED, encoding="utf-8")
    code, out, err = fmt(runner, path, "--check", "--number")
    assert code == 0
    assert out == ""
    assert "already formatted" in err


def test_output_file_leaves_the_input_alone(runner: CliRunner, tmp_path: Path) -> None:
    path, out_path = tmp_path / "a.MB4", tmp_path / "b.MB4"
    path.write_text(MESSY, encoding="utf-8")
    assert fmt(runner, path, "--number", "-o", out_path)[0] == 0
    assert path.read_text(encoding="utf-8") == MESSY
    assert out_path.read_text(encoding="utf-8") == NUMBERED


def test_output_dash_is_stdout(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(MESSY, encoding="utf-8")
    code, out, _ = fmt(runner, path, "--number", "-o", "-")
    assert code == 0
    assert out == NUMBERED
    assert path.read_text(encoding="utf-8") == MESSY


def test_missing_jump_target_refuses_and_writes_nothing(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text("mov p1\ngoto 30\n", encoding="utf-8")
    code, _, err = fmt(runner, path, "--number")
    assert code == 1
    assert f"{path}:2:6: error: GOTO 30: there is no step 30 [L4230]" in err
    assert "nothing written" in err
    assert path.read_text(encoding="utf-8") == "mov p1\ngoto 30\n"


def test_syntax_errors_are_formatted_without_damage(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text('movv p1 ?? "open\nhopen\n', encoding="utf-8")
    assert fmt(runner, path, "--number")[0] == 0
    assert path.read_text(encoding="utf-8") == '10 movv p1 ?? "open\n20 HOPEN\n'


def test_empty_file(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_bytes(b"")
    assert fmt(runner, path, "--number")[0] == 0
    assert path.read_bytes() == b""


@pytest.mark.parametrize(
    ("name", "content", "args", "expected"),
    [
        ("a.MB4", "END\n", ("--number", "--strip"), "cannot be used together"),
        ("a.POS", "Pa=(1,2,3,4,5,6)(7,0)\n", (), "formats programs (.MB4)"),
        ("a.txt", "END\n", (), "unknown file type (.txt)"),
        ("bin.MB4", b"ROBPRG\x00\x00", (), "not a text file"),
    ],
)
def test_usage_errors_exit_2(
    runner: CliRunner,
    tmp_path: Path,
    name: str,
    content: str | bytes,
    args: tuple[str, ...],
    expected: str,
) -> None:
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    before = path.read_bytes()
    code, _out, err = fmt(runner, path, *args)
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1
    assert expected in err
    assert path.read_bytes() == before


def test_missing_file_and_directory(runner: CliRunner, tmp_path: Path) -> None:
    code, _, err = fmt(runner, tmp_path / "none.MB4")
    assert code == 2 and "no such file" in err
    (tmp_path / "dir.MB4").mkdir()
    code, _, err = fmt(runner, tmp_path / "dir.MB4")
    assert code == 2 and "is a directory" in err


def test_unwritable_output_is_a_usage_error(runner: CliRunner, tmp_path: Path) -> None:
    path = tmp_path / "a.MB4"
    path.write_text(MESSY, encoding="utf-8")
    code, _, err = fmt(runner, path, "-o", tmp_path / "no" / "such" / "dir.MB4")
    assert code == 2
    assert "cannot write" in err
