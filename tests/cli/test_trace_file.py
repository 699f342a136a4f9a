"""`--trace FILE` as docs/bringup.md shows it: one line per request and one per reply, even
when the serial port hands each reply over a few bytes at a time (a paced pty at 9600 baud,
like the real line), and still every byte, replayable."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.link import load_trace
from melfa.sim import Pacing, PtyServer, VirtualController

runner = CliRunner()


@pytest.fixture(autouse=True)
def _profile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MELFA_PROFILE", str(tmp_path / "profile.json"))


def test_a_trace_has_one_line_per_reply_over_a_paced_serial_line(tmp_path: Path) -> None:
    trace = tmp_path / "first-day.trace"
    with PtyServer(VirtualController(), pacing=Pacing.for_baud(9600)) as server:
        result = runner.invoke(app, ["status", "--robot", server.new_port(), "--trace", str(trace)])
    assert result.exit_code == 0, result.output
    lines = trace.read_text(encoding="utf-8").splitlines()
    sent = [line for line in lines if " -> " in line]
    received = [line for line in lines if " <- " in line]
    assert len(sent) >= 3
    assert len(received) == len(sent), lines  # a reply each, each on one line
    assert all(line.split("  [")[0].endswith("<CR>") for line in received), received
    events = load_trace(lines)
    assert all(e.data.endswith(b"\r") and e.data.count(b"\r") == 1 for e in events)
