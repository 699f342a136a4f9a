"""`melfa check`: exit codes, text and JSON output, and every way a file can be odd."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from melfa.cli import app
from melfa.cli.checking import FileKind, FileReport, SourceFile, summary_line
from melfa.lang.diagnostics import Diagnostic, Severity

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

SAMPLE = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"
POINTS = (
    "DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)\n"
    "DEF POS Pb=(225.48,-363.55,683.37,-128.32,2.12,-123.50)(7,0)\n"
)
BROKEN = "10 SERVO ON\n20 MOVV Pa\n30 END\n"  # MOVV: L4220 at 2:4


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


def write(folder: Path, name: str, content: str | bytes) -> Path:
    path = folder / name
    if isinstance(content, str):
        content = content.encode("utf-8")
    path.write_bytes(content)
    return path


def run(runner: CliRunner, *args: str | Path) -> tuple[int, str, str]:
    result = runner.invoke(app, ["check", *map(str, args)])
    assert not isinstance(result.exception, Exception) or isinstance(
        result.exception, SystemExit
    ), result.exception
    return result.exit_code, result.stdout, result.stderr


def as_json(runner: CliRunner, *args: str | Path) -> tuple[int, list[dict[str, object]]]:
    code, out, _ = run(runner, *args, "--format", "json")
    return code, json.loads(out)


# --- exit codes and output ---------------------------------------------------------------


def test_a_clean_program_with_its_points_exits_0(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "sample.MB4", SAMPLE)
    pos = write(tmp_path, "sample.POS", POINTS)
    code, out, err = run(runner, prog, "--points", pos)
    assert code == 0, out
    assert out.strip().splitlines()[-1] == "0 errors, 0 warnings in 2 files"
    assert err == ""


def test_an_error_exits_1_and_reads_like_a_compiler(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "broken.mb4", BROKEN)
    code, out, _ = run(runner, prog)
    assert code == 1
    first = out.splitlines()[0]
    assert first.startswith(f"{prog}:2:4: error: ")
    assert first.endswith("[L4220]")
    assert "MOVV" in first
    assert "  = help: Replace with MOV.\n" in out
    assert out.splitlines()[-1].startswith("1 error, ")
    assert "\x1b[" not in out  # plain when piped
    assert "| 20 MOVV" not in out  # no source excerpt when piped


def test_colour_always_shows_the_source_line_and_caret(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "broken.MB4", BROKEN)
    result = runner.invoke(app, ["check", str(prog), "--color", "always"])
    assert result.exit_code == 1
    assert "\x1b[" in result.stdout
    plain = _strip_ansi(result.stdout)
    lines = plain.splitlines()
    source = next(i for i, line in enumerate(lines) if line.endswith("| 20 MOVV Pa"))
    caret_line = lines[source + 1]
    assert caret_line.index("^") == lines[source].index("MOVV")
    assert caret_line.rstrip().endswith("^^^^")


def test_caret_lines_up_under_tabs(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "tabs.MB4", "10\tSERVO ON\n20\tMOVV\tPa\n")
    result = runner.invoke(app, ["check", str(prog), "--color", "always"])
    plain = _strip_ansi(result.stdout).splitlines()
    source = next(i for i, line in enumerate(plain) if "MOVV" in line and "|" in line)
    # The padding copies the tab, so the caret sits under M however tabs are expanded.
    src_line, caret_line = plain[source], plain[source + 1]
    assert caret_line.expandtabs(8).index("^") == src_line.expandtabs(8).index("MOVV")


def test_json_shape_is_exact(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "broken.MB4", BROKEN)
    code, data = as_json(runner, prog)
    assert code == 1
    assert isinstance(data, list) and len(data) == 1
    entry = data[0]
    assert set(entry) == {"file", "diagnostics"}
    assert entry["file"] == str(prog)
    diagnostics = entry["diagnostics"]
    assert isinstance(diagnostics, list)
    first = diagnostics[0]
    assert set(first) == {
        "line",
        "column",
        "end_line",
        "end_column",
        "severity",
        "code",
        "rule",
        "message",
        "suggestion",
        "replace",
    }
    assert (first["line"], first["column"], first["end_line"], first["end_column"]) == (2, 4, 2, 8)
    assert (first["severity"], first["code"]) == ("error", "L4220")


def test_json_of_a_clean_program_is_an_empty_list_of_diagnostics(
    runner: CliRunner, tmp_path: Path
) -> None:
    prog = write(tmp_path, "ok.MB4", "SERVO ON\nEND\n")
    code, data = as_json(runner, prog)
    assert code == 0
    assert data == [{"file": str(prog), "diagnostics": []}]


def test_points_file_alone_is_checked_as_points(runner: CliRunner, tmp_path: Path) -> None:
    pos = write(tmp_path, "bad.pos", POINTS + "DEF POS Pc=(1,2,x,4,5,6)(7,0)\n")
    code, data = as_json(runner, pos)
    assert code == 1
    [entry] = data
    [d] = entry["diagnostics"]  # type: ignore[misc]
    assert (d["line"], d["column"], d["code"]) == (3, 17, "L3860")


def test_points_diagnostics_are_reported_against_the_points_file(
    runner: CliRunner, tmp_path: Path
) -> None:
    prog = write(tmp_path, "sample.MB4", SAMPLE)
    pos = write(tmp_path, "sample.POS", POINTS + "Pa=(1,2,3,4,5,6)(7,0)\n")
    code, data = as_json(runner, prog, "--points", pos)
    assert code == 1
    assert [e["file"] for e in data] == [str(prog), str(pos)]
    assert data[0]["diagnostics"] == []
    [dup] = data[1]["diagnostics"]  # type: ignore[misc]
    assert dup["code"] == "L4350" and dup["line"] == 3


def test_a_pos_file_among_the_files_supplies_names_once(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "sample.MB4", SAMPLE)
    pos = write(tmp_path, "sample.POS", POINTS)
    code, data = as_json(runner, prog, pos, "--points", pos)
    assert code == 0
    assert [e["file"] for e in data] == [str(prog), str(pos)]


def test_warnings_alone_exit_0() -> None:
    d = Diagnostic(1, 1, 1, 2, Severity.WARNING, "unused label", "x")
    report = FileReport(Path("a.MB4"), SourceFile(Path("a.MB4"), FileKind.PROGRAM, b""), [d])
    assert summary_line([report]) == "0 errors, 1 warning in 1 file"


def test_summary_counts_and_plurals() -> None:
    def diag(severity: Severity) -> Diagnostic:
        return Diagnostic(1, 1, 1, 2, severity, "m", "r")

    source = SourceFile(Path("a.MB4"), FileKind.PROGRAM, b"")
    reports = [
        FileReport(Path("a.MB4"), source, [diag(Severity.ERROR), diag(Severity.ERROR)]),
        FileReport(Path("b.MB4"), source, [diag(Severity.WARNING), diag(Severity.INFO)]),
    ]
    assert summary_line(reports) == "2 errors, 1 warning, 1 info in 2 files"


def test_bundled_examples_pass(runner: CliRunner) -> None:
    for name in ("sample", "thesis_test", "pyramid"):
        code, out, _ = run(runner, EXAMPLES / f"{name}.MB4", "--points", EXAMPLES / f"{name}.POS")
        assert code == 0, out
        assert "0 errors" in out


# --- odd files ---------------------------------------------------------------------------


def test_empty_file_is_fine(runner: CliRunner, tmp_path: Path) -> None:
    code, data = as_json(runner, write(tmp_path, "empty.MB4", b""))
    assert code == 0
    assert data[0]["diagnostics"] == []


def test_empty_points_file_is_fine(runner: CliRunner, tmp_path: Path) -> None:
    code, _, _ = run(runner, write(tmp_path, "empty.POS", b""))
    assert code == 0


def test_latin1_file_is_read_and_columns_count_characters(
    runner: CliRunner, tmp_path: Path
) -> None:
    text = "10 ' Posició de la piràmide\n20 MOVV Pa\n"
    prog = write(tmp_path, "cat.MB4", text.encode("latin-1"))
    code, data = as_json(runner, prog)
    assert code == 1
    d = data[0]["diagnostics"][0]  # type: ignore[index]
    assert (d["line"], d["column"]) == (2, 4)


def test_utf8_with_accents_and_bom(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "u.MB4", b"\xef\xbb\xbf" + "' Posició\nMOVV Pa\n".encode())
    code, data = as_json(runner, prog)
    assert code == 1
    d = data[0]["diagnostics"][0]  # type: ignore[index]
    assert (d["line"], d["column"]) == (2, 1)


def test_utf16_with_bom_is_read(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "w.MB4", "SERVO ON\r\nEND\r\n".encode("utf-16"))
    code, _, out = run(runner, prog)
    assert code == 0, out


def test_binary_file_is_a_clear_diagnostic_not_a_traceback(
    runner: CliRunner, tmp_path: Path
) -> None:
    prog = write(tmp_path, "bin.MB4", b"ROBPRG\x00\x01\x02\xff\xfe")
    code, out, _ = run(runner, prog)
    assert code == 1
    assert f"{prog}:1:7: error: This is not a text file" in out
    assert "Traceback" not in out


def test_tabs_and_crlf_are_fine(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "tabs.MB4", "10\tSERVO ON\r\n20\tOVRD\t20\r\n30\tEND\r\n")
    code, out, _ = run(runner, prog)
    assert code == 0, out


def test_very_long_line(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "long.MB4", "10 M1 = " + " + ".join(["1"] * 5000) + "\n20 MOVV P1\n")
    result = runner.invoke(app, ["check", str(prog), "--color", "always"])
    assert result.exit_code == 1
    assert all(len(_strip_ansi(line)) < 400 for line in result.stdout.splitlines())


# --- usage errors ------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("setup", "expected"),
    [
        (lambda d: d / "missing.MB4", "no such file"),
        (lambda d: _mkdir(d / "folder.MB4"), "is a directory"),
        (lambda d: write(d, "prog.txt", "END\n"), "unknown file type (.txt)"),
        (lambda d: write(d, "prog", "END\n"), "unknown file type (no extension)"),
    ],
)
def test_usage_errors_exit_2_with_one_red_line(
    runner: CliRunner, tmp_path: Path, setup: object, expected: str
) -> None:
    path = setup(tmp_path)  # type: ignore[operator]
    code, out, err = run(runner, path)
    assert code == 2
    assert out == ""
    assert err.count("\n") == 1
    assert err.startswith("error: ")
    assert expected in err
    assert str(path) in err


def test_points_option_must_be_a_points_file(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "a.MB4", SAMPLE)
    code, _, err = run(runner, prog, "--points", prog)
    assert code == 2
    assert "--points takes a .POS" in err


def test_missing_points_file(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "a.MB4", SAMPLE)
    code, _, err = run(runner, prog, "--points", tmp_path / "none.POS")
    assert code == 2
    assert "no such file" in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file")
def test_unreadable_file(runner: CliRunner, tmp_path: Path) -> None:
    prog = write(tmp_path, "secret.MB4", SAMPLE)
    prog.chmod(0)
    code, _, err = run(runner, prog)
    assert code == 2
    assert "cannot read" in err


def test_no_files_and_bad_format_are_usage_errors(runner: CliRunner, tmp_path: Path) -> None:
    assert runner.invoke(app, ["check"]).exit_code == 2
    prog = write(tmp_path, "a.MB4", SAMPLE)
    assert runner.invoke(app, ["check", str(prog), "--format", "xml"]).exit_code == 2


# --- the real console script -------------------------------------------------------------


def test_console_script_in_a_subprocess(tmp_path: Path) -> None:
    script = Path(sys.executable).with_name("melfa")
    command = [str(script)] if script.exists() else [sys.executable, "-m", "melfa"]
    prog = write(tmp_path, "broken.MB4", BROKEN)
    done = subprocess.run(
        [*command, "check", str(prog), "--format", "json"],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 1, done.stderr
    assert json.loads(done.stdout)[0]["diagnostics"][0]["code"] == "L4220"
    done = subprocess.run(
        [
            *command,
            "check",
            str(EXAMPLES / "pyramid.MB4"),
            "--points",
            str(EXAMPLES / "pyramid.POS"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    done = subprocess.run(
        [*command, "check", str(tmp_path / "nope.MB4")],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert done.returncode == 2
    assert "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines() == [f"error: {tmp_path / 'nope.MB4'}: no such file"]


def _mkdir(path: Path) -> Path:
    path.mkdir()
    return path


def _strip_ansi(text: str) -> str:
    return re.sub(r"\x1b\[[0-9;]*m", "", text)


@settings(max_examples=40)
@given(st.binary(max_size=300), st.sampled_from(["x.MB4", "x.POS"]))
def test_any_bytes_give_a_report_never_a_traceback(data: bytes, name: str) -> None:
    with tempfile.TemporaryDirectory() as folder:
        path = write(Path(folder), name, data)
        result = CliRunner().invoke(app, ["check", str(path), "--format", "json"])
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert result.exit_code in (0, 1)
    [entry] = json.loads(result.stdout)
    assert entry["file"] == str(path)


# --- reachability of the points (melfa.kin.reach) ------------------------------------------

FAR_POINTS = (
    "DEF POS Pok=(400,0,450,180,0,180)(7,0)\n"
    "DEF POS Pfar=(1200,0,450,180,0,180)(7,0)\n"
    "DEF POS Pflag=(400,0,450,180,0,180)(3,0)\n"
    "DEF JNT Jbad=(0,140,90,0,90,0)\n"
)


@pytest.mark.parametrize("as_option", [False, True])
def test_unreachable_points_warn_on_their_lines(
    runner: CliRunner, tmp_path: Path, as_option: bool
) -> None:
    prog = write(tmp_path, "far.MB4", "MOV Pok\nMOV Pfar\nMOV Pflag\nMOV Jbad\n")
    pos = write(tmp_path, "far.POS", FAR_POINTS)
    args = (prog, "--points", pos) if as_option else (prog, pos)
    code, out, _ = run(runner, *args)
    assert code == 0, out  # warnings only
    assert f"{pos}:2:9: warning: Point Pfar is out of the RV-6S's reach (" in out
    assert f"{pos}:3:9: warning: Point Pflag is reachable only with flags (7,0), not (3,0)\n" in out
    assert f"{pos}:4:9: warning: Point Jbad has J2 = 140°, beyond its limit -92…135°\n" in out
    assert "  = help: Change the flags to (7,0)" in out
    assert out.splitlines()[-1] == "0 errors, 3 warnings in 2 files"


def test_a_points_file_alone_gets_the_reach_warnings_in_json(
    runner: CliRunner, tmp_path: Path
) -> None:
    pos = write(tmp_path, "far.pos", FAR_POINTS)
    code, data = as_json(runner, pos)
    assert code == 0
    diagnostics = data[0]["diagnostics"]
    assert isinstance(diagnostics, list)
    found = [(d["line"], d["column"], d["end_column"], d["severity"]) for d in diagnostics]
    assert found == [(2, 9, 13, "warning"), (3, 9, 14, "warning"), (4, 9, 13, "warning")]
