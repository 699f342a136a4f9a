"""`melfa sim` in a subprocess: it prints where it listens, serves, stops cleanly."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import serial
from typer.testing import CliRunner

from melfa.cli import app

RUN = [sys.executable, "-m", "melfa", "sim"]


def _first_line_with(proc: subprocess.Popen[str], needle: str) -> str:
    assert proc.stdout is not None
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if needle in line:
            return line
    raise AssertionError(f"no line with {needle!r}")


def _stop(proc: subprocess.Popen[str]) -> str:
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=20)
    return out


def test_pty_mode_serves_a_pyserial_client_and_prints_the_next_path() -> None:
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(
        [*RUN, "--pty", "--no-pacing"], stdout=subprocess.PIPE, text=True, env=env
    )
    try:
        line = _first_line_with(proc, "listening on")
        path = line.split("listening on ")[1].split()[0]
        with serial.Serial(path, 9600, parity="E", stopbits=2, timeout=10) as port:
            port.write(b"1;1;OPEN=CLI\r")
            reply = port.read_until(b"\r")
            assert reply.startswith(b"QoK3F;3F;")
        assert "listening on" in _first_line_with(proc, "listening on")  # the next pty
    finally:
        out = _stop(proc)
    assert "virtual controller stopped" in out
    assert proc.returncode == 0


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
