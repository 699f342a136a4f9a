"""docs/bringup.md's steps run as written against the simulator: every `melfa` command in
its console blocks, with `/dev/ttyUSB0` replaced by a pty of the virtual controller (a fresh
pty per command, as a real port is opened per command), in order, each exiting 0.

The controller's clock runs 50 times faster than the wall clock (an injected clock), so
`melfa run --wait` of the pyramid program at override 10 % ends in seconds."""

from __future__ import annotations

import re
import shlex
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.sim import NO_PACING, PtyServer, SimConfig, VirtualController

ROOT = Path(__file__).resolve().parents[2]
GUIDE = ROOT / "docs" / "bringup.md"
SPEEDUP = 50.0


def guide_commands() -> list[list[str]]:
    """The `$ melfa …` lines of the guide's console blocks, as argument lists."""
    text = GUIDE.read_text(encoding="utf-8")
    blocks = re.findall(r"```console\n(.*?)```", text, flags=re.S)
    lines = [line[2:] for block in blocks for line in block.splitlines() if line.startswith("$ ")]
    commands = [shlex.split(line, comments=True) for line in lines]
    assert all(c[0] == "melfa" for c in commands)
    return [c[1:] for c in commands]


def test_the_guide_has_the_steps_it_promises() -> None:
    names = [c[0] for c in guide_commands()]
    assert names == ["doctor", "doctor", "upload", "servo", "override", "run"]


def test_every_bringup_step_runs_as_written_against_the_simulator(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("MELFA_PROFILE", str(tmp_path / "profile.json"))
    monkeypatch.chdir(tmp_path)
    controller = VirtualController(SimConfig(strict=True))
    start = time.monotonic()
    fast = lambda: start + (time.monotonic() - start) * SPEEDUP  # noqa: E731
    runner = CliRunner()
    with PtyServer(controller, pacing=NO_PACING, clock=fast) as server:
        for command in guide_commands():
            port = server.new_port()
            args = [
                port if a == "/dev/ttyUSB0" else str(ROOT / a) if a.startswith("examples/") else a
                for a in command
            ]
            result = runner.invoke(app, args)
            assert result.exit_code == 0, (command, result.output)
            assert "Traceback" not in result.output
    assert (tmp_path / "first-day.txt").read_text(encoding="utf-8").rstrip().endswith("usable")
    assert (tmp_path / "first-day.trace").exists()
    assert controller.store.get("1") is not None
    assert "MDOCTOR" not in controller.store
