"""examples/systemd/melfa.service: its ExecStart is a `melfa serve` that starts, and stopping
it as systemd does (KillSignal) ends it cleanly with a status the unit counts as success."""

from __future__ import annotations

import os
import re
import shlex
import signal
import subprocess
import sys
from pathlib import Path

from melfa.cli import EXIT_INTERRUPTED

ROOT = Path(__file__).resolve().parents[2]
UNIT = ROOT / "examples" / "systemd" / "melfa.service"


def settings() -> dict[str, list[str]]:
    found: dict[str, list[str]] = {}
    for line in UNIT.read_text(encoding="utf-8").splitlines():
        if "=" in line and not line.startswith(("#", "[")):
            key, value = line.split("=", 1)
            found.setdefault(key, []).append(value)
    return found


def test_the_unit_stops_melfa_as_ctrl_c_and_counts_that_as_success() -> None:
    unit = settings()
    assert unit["KillSignal"] == ["SIGINT"]
    assert str(EXIT_INTERRUPTED) in unit["SuccessExitStatus"][0].split()
    assert unit["SupplementaryGroups"] == ["dialout"]  # the serial port
    assert "MELFA_DATA=/var/lib/melfa" in unit["Environment"]
    assert unit["ReadWritePaths"] == ["/var/lib/melfa"]


def test_its_exec_start_serves_and_stops_cleanly(tmp_path: Path) -> None:
    [command] = settings()["ExecStart"]
    words = shlex.split(command)
    assert words[0] == "/opt/melfa/.venv/bin/melfa" and words[1] == "serve"
    # Run as written but for where it is installed, the port (a free one) and the robot.
    args = [re.sub(r"^8080$", "0", w) for w in words[1:]]
    env = {k: v for k, v in os.environ.items() if not k.startswith("MELFA_")}
    env.update(MELFA_DATA=str(tmp_path), MELFA_ROBOT="sim", MELFA_ADMIN_PASSWORD="unit-pass-1")
    proc = subprocess.Popen(
        [sys.executable, "-m", "melfa", *args],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    assert proc.stdout is not None
    try:
        line = proc.stdout.readline()
        assert "melfa serving on http://127.0.0.1:" in line, line
    finally:
        os.killpg(proc.pid, getattr(signal, settings()["KillSignal"][0]))
        rest, _ = proc.communicate(timeout=60)
    assert str(proc.returncode) in settings()["SuccessExitStatus"][0].split(), rest
    assert "melfa stopped" in rest and "Traceback" not in rest
