"""`melfa doctor` through a real pty at 9600 8E2: read-only by default, the verdicts, the
profile it writes (and later commands read), exit codes 0 / 1 / 3."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.link import load_trace
from melfa.protocol import Kind, lookup
from melfa.robot.profile import profile_settings
from melfa.sim import NO_PACING, KeySwitch, PtyServer, SimConfig
from tests.service.helpers import RecordingController

runner = CliRunner()


@pytest.fixture
def profile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    path = tmp_path / "profile.json"
    monkeypatch.setenv("MELFA_PROFILE", str(path))
    monkeypatch.chdir(tmp_path)  # the report file (melfa-doctor.txt) lands here, not in the repo
    return path


def _doctor(controller: RecordingController, *extra: str) -> tuple[int, str, str]:
    with PtyServer(controller, pacing=NO_PACING) as server:
        port = server.new_port()
        result = runner.invoke(app, ["doctor", "--robot", port, "--timeout", "5", *extra])
    return result.exit_code, result.output, port


def test_doctor_is_read_only_and_writes_the_profile(profile: Path) -> None:
    controller = RecordingController()
    code, output, port = _doctor(controller)
    assert code == 0, output
    assert "mode key" in output and "STOP form" in output and "1;1;STOP accepted" in output
    sent = [line.split(";", 2)[-1] for line in controller.commands()]
    for command in sent:
        spec = lookup(command)
        assert spec is not None, command
        if command == "OVRD=100":  # the operation-rights probe writes the value STATE showed
            continue
        assert spec.kind in (Kind.SESSION, Kind.READ, Kind.STOP), command
    stored = json.loads(profile.read_text())["robots"][port]
    assert stored["settings"]["stop_slot"] == 1
    assert profile_settings(port).stop_slot == 1


def test_doctor_in_teach_mode_exits_1(profile: Path) -> None:
    controller = RecordingController(SimConfig(key=KeySwitch.TEACH))
    code, output, _ = _doctor(controller)
    assert code == 1, output
    assert "TEACH" in output and "Traceback" not in output


def test_doctor_probe_upload_writes_reads_back_and_deletes_a_scratch_program(
    profile: Path,
) -> None:
    controller = RecordingController()
    code, output, port = _doctor(controller, "--probe-upload")
    assert code == 0, output
    assert "identical" in output or "LISTPTOP" in output, output  # strict: LISTP unseen
    assert "MDOCTOR" not in controller.store
    assert any(c.endswith("FDELMDOCTOR") for c in controller.commands())
    assert json.loads(profile.read_text())["robots"][port]["settings"]["confirm_counts"] is True


def test_doctor_link_failure_exits_3(profile: Path) -> None:
    result = runner.invoke(app, ["doctor", "--robot", "/dev/melfa-no-such-port"])
    assert result.exit_code == 3, result.output


@pytest.mark.parametrize("value", ["", " ", "tcp://nohost", "ftp://x", "not a port"])
def test_empty_or_malformed_robot_values_are_usage_errors(value: str, profile: Path) -> None:
    for command in (["pose"], ["doctor"], ["stop"]):
        result = runner.invoke(app, [*command, "--robot", value])
        assert result.exit_code == 2, (command, value, result.output)
        assert "--robot" in result.output and "Traceback" not in result.output


def test_trace_file_records_every_byte_both_ways_and_replays(tmp_path: Path, profile: Path) -> None:
    trace = tmp_path / "session.trace"
    controller = RecordingController()
    with PtyServer(controller, pacing=NO_PACING) as server:
        result = runner.invoke(app, ["status", "--robot", server.new_port(), "--trace", str(trace)])
    assert result.exit_code == 0, result.output
    events = load_trace(trace.read_text(encoding="utf-8").splitlines())
    sent = b"".join(e.data for e in events if e.direction == "->")
    received = b"".join(e.data for e in events if e.direction == "<-")
    assert sent.split(b"\r")[:-1] == [c.encode() for c in controller.commands()]
    assert [e.seconds for e in events] == sorted(e.seconds for e in events)
    # Replayed against a fresh virtual controller, the requests give the same replies.
    fresh = RecordingController()
    replayed = b"".join(fresh.handle(line + b"\r", 0.0) for line in sent.split(b"\r")[:-1])
    assert replayed == received
