"""`melfa stop` while another command holds the serial port: a clear message, exit 3, no
traceback; `melfa override N` sets the operation-panel override. Real ptys at 9600 8E2."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.link import LinkBusy, SerialLink, TcpLink
from melfa.sim import NO_PACING, PtyServer, TcpServer, VirtualController

runner = CliRunner()


@pytest.fixture(autouse=True)
def profile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MELFA_PROFILE", str(tmp_path / "profile.json"))


def test_melfa_stop_on_a_held_port_says_who_holds_it_and_how_to_stop() -> None:
    with PtyServer(pacing=NO_PACING) as server:
        port = server.new_port()
        holder = SerialLink(port)  # another melfa command (a `melfa run --wait`) holds it
        try:
            with pytest.raises(LinkBusy):
                SerialLink(port)
            result = runner.invoke(app, ["stop", "--robot", port, "--timeout", "2"])
        finally:
            holder.close()
    assert result.exit_code == 3, result.output
    assert "another program holds it" in result.output and "Ctrl-C" in result.output
    assert "Traceback" not in result.output and "termios" not in result.output


def test_melfa_override_sets_the_panel_override() -> None:
    controller = VirtualController()
    with PtyServer(controller, pacing=NO_PACING) as server:
        result = runner.invoke(app, ["override", "30", "--robot", server.new_port()])
    assert result.exit_code == 0, result.output
    assert "override 30 %" in result.output
    assert controller.handle(b"1;1;STATE\r", 0.0).split(b";")[2] == b"30"


def test_melfa_override_outside_1_to_100_is_a_usage_error() -> None:
    result = runner.invoke(app, ["override", "0", "--robot", "sim"])
    assert result.exit_code == 2


def test_melfa_stop_against_a_tcp_simulator_another_command_holds() -> None:
    with TcpServer(pacing=NO_PACING) as server:
        holder = TcpLink(server.url)
        try:
            holder.write(b"1;1;STATE\r")
            holder.read_reply(5)  # the first client is served
            result = runner.invoke(app, ["stop", "--robot", server.url, "--timeout", "2"])
        finally:
            holder.close()
    assert result.exit_code == 3, result.output
    assert "another program holds it" in result.output and "Traceback" not in result.output
