"""`melfa sim` in a subprocess: it prints where it listens, serves, stops cleanly."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import serial
from typer.testing import CliRunner

from melfa.cli import app

RUN = [sys.executable, "-m", "melfa", "sim"]


def _first_line_with(proc: subprocess.Popen[str], needle: str) -> str:
    assert proc.stdout is not None
    deadline = time.monotonic() + 60  # generous: a loaded machine starts Python slowly
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if needle in line:
            return line
    raise AssertionError(f"no line with {needle!r}")


def _stop(proc: subprocess.Popen[str]) -> str:
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    return out


def test_pty_mode_serves_a_pyserial_client_and_prints_the_next_path() -> None:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [*RUN, "--pty", "--no-pacing"], stdout=subprocess.PIPE, text=True, env=env
    )
    try:
        line = _first_line_with(proc, "listening on")
        path = line.split("listening on ")[1].split()[0]
        with serial.Serial(path, 9600, parity="E", stopbits=2, timeout=30) as port:
            port.write(b"1;1;OPEN=CLI\r")
            reply = port.read_until(b"\r")
            assert reply.startswith(b"QoK3F;3F;")
        assert "listening on" in _first_line_with(proc, "listening on")  # the next pty
    finally:
        out = _stop(proc)
    assert "virtual controller stopped" in out
    assert proc.returncode == 130  # Ctrl-C: status 130, as every melfa command


def test_tcp_mode_prints_its_url() -> None:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [*RUN, "--tcp", "127.0.0.1:0"], stdout=subprocess.PIPE, text=True, env=env
    )
    try:
        line = _first_line_with(proc, "listening on")
        assert "tcp://127.0.0.1:" in line
    finally:
        out = _stop(proc)
    assert "virtual controller stopped" in out


def test_usage_mistakes_are_one_line_and_exit_2() -> None:
    runner = CliRunner()
    result = runner.invoke(app, ["sim", "--tcp", "nonsense"])
    assert result.exit_code == 2
    assert "HOST:PORT" in result.output
    result = runner.invoke(app, ["sim", "--baud", "1234"])
    assert result.exit_code == 2
    result = runner.invoke(app, ["sim", "--pty", "--tcp", ":0"])
    assert result.exit_code == 2


# ------------------------------------------------------------------------------------ --run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_run_traces_a_program_and_exits_with_its_code(tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(
        app,
        [
            "sim",
            "--run",
            str(EXAMPLES / "sample.MB4"),
            "--points",
            str(EXAMPLES / "sample.POS"),
            "--fast",
        ],
    )
    assert result.exit_code == 0, result.output
    assert result.output.splitlines()[-1].startswith("finished at line 70 after")
    bad = tmp_path / "BAD.MB4"
    bad.write_text("10 M1 = 1 / 0\n20 END\n")
    result = runner.invoke(app, ["sim", "--run", str(bad), "--fast"])
    assert result.exit_code == 1
    assert "error in line 10:" in result.output and "Traceback" not in result.output
    assert result.output.splitlines()[-1] == "    10 M1 = 1 / 0"


def test_run_inputs_are_set_before_the_program_starts(tmp_path: Path) -> None:
    prog = tmp_path / "W.MB4"
    prog.write_text("10 WAIT M_IN(3) = 1 AND M_IN(4) = 0\n20 HOPEN 1\n30 END\n")
    runner = CliRunner()
    args = ["sim", "--run", str(prog), "--fast", "--max-time", "2"]
    waiting = runner.invoke(app, args)
    assert waiting.exit_code == 0
    assert waiting.output.splitlines()[-1].startswith("waiting (WAIT) at line 10")
    done = runner.invoke(app, [*args, "--input", "3=1", "--input", "4=0"])
    assert done.exit_code == 0
    assert done.output.splitlines()[-1].startswith("finished at line 30")


def test_run_usage_mistakes_exit_2(tmp_path: Path) -> None:
    runner = CliRunner()
    prog = tmp_path / "P.MB4"
    prog.write_text("10 END\n")
    for args in (
        ["--run", str(prog), "--input", "3"],
        ["--run", str(prog), "--input", "3=2"],
        ["--run", str(prog), "--tcp", ":0"],
        ["--run", str(prog), "--max-time", "0"],
        ["--fast"],
        ["--points", str(prog)],
        ["--input", "1=1"],
    ):
        result = runner.invoke(app, ["sim", *args])
        assert result.exit_code == 2, (args, result.output)
        assert "Traceback" not in result.output
    missing = runner.invoke(app, ["sim", "--run", str(tmp_path / "NOPE.MB4")])
    assert missing.exit_code == 2 and "NOPE.MB4: no such file" in missing.output


def test_run_into_a_closed_pipe_is_quiet(tmp_path: Path) -> None:
    endless = tmp_path / "LOOP.MB4"
    endless.write_text("10 DLY 0.01\n20 GOTO 10\n")  # far more output than a pipe holds
    proc = subprocess.run(
        f"{sys.executable} -m melfa sim --run {endless} --fast --max-time 600 | head -n 2",
        shell=True,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert len(proc.stdout.splitlines()) == 2
    assert proc.stderr == ""


def test_real_situation_options_reach_the_served_controller() -> None:
    """`--key teach --digits 4 --strict --no-origin`: a controller to rehearse with."""
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    options = ["--pty", "--no-pacing", "--key", "teach", "--digits", "4", "--strict"]
    proc = subprocess.Popen(
        [*RUN, *options, "--no-origin"], stdout=subprocess.PIPE, text=True, env=env
    )
    try:
        line = _first_line_with(proc, "listening on")
        path = line.split("listening on ")[1].split()[0]
        assert "MODE key TEACH" in _first_line_with(proc, "MODE key")
        with serial.Serial(path, 9600, parity="E", stopbits=2, timeout=30) as port:
            for request, expected in (
                (b"1;1;OPEN=CLI\r", b"QoK3F;3F;"),
                (b"1;1;CNTLON\r", b"QoK\r"),
                (b"1;1;SLOTINIT\r", b"QeR6020\r"),  # TEACH, 4 digits
                (b"1;1;HNDSTS\r", b"QeR6010\r"),  # strict
                (b"1;1;PPOSF\r", b"QoKX;****;"),  # origin not set
            ):
                port.write(request)
                assert port.read_until(b"\r").startswith(expected), request
    finally:
        _stop(proc)


def test_digits_other_than_4_or_9_are_a_usage_mistake() -> None:
    result = CliRunner().invoke(app, ["sim", "--digits", "5"])
    assert result.exit_code == 2 and "4 (manual) or 9 (real)" in result.output


def test_pty_link_is_a_stable_name_and_the_baud_is_printed_as_given(tmp_path: Path) -> None:
    link = tmp_path / "robot"
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [*RUN, "--pty", "--no-pacing", "--baud", "38400", "--cterm", "1", "--link", str(link)],
        stdout=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        line = _first_line_with(proc, "listening on")
        assert "(38400 8E2)" in line and str(link) in line
        for _ in range(2):  # the same name serves the next client on a fresh pty
            with serial.Serial(str(link), 38400, parity="E", stopbits=2, timeout=30) as port:
                port.write(b"1;1;STATE\r")  # no OPEN: real controllers answered that
                assert port.readline().endswith(b"\r\n")  # CTERM232 = 1
            _first_line_with(proc, "listening on")
    finally:
        _stop(proc)
    assert not link.exists()
