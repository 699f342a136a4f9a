"""`melfa upload|run|stop|…` in process (CliRunner) against a persistent simulator on a
fresh pty per invocation, opened at 9600 8E2 like a real port."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

import melfa.cli.robot_commands
from melfa.cli.app import app
from melfa.cli.robot_commands import FIRST_REPEAT_S, REPEAT_GAP_S, JogKeys
from melfa.sim import PtyServer, VirtualController

runner = CliRunner()

PROGRAM = "SERVO ON\nMOV P1\nHOPEN 1\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,450.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture
def controller() -> VirtualController:
    return VirtualController()


@pytest.fixture
def server(controller: VirtualController) -> Iterator[PtyServer]:
    with PtyServer(controller) as s:
        yield s


@pytest.fixture
def files(tmp_path: Path) -> tuple[Path, Path]:
    program = tmp_path / "demo.MB4"
    points = tmp_path / "demo.POS"
    program.write_text(PROGRAM)
    points.write_text(POINTS)
    return program, points


def melfa(server: PtyServer, *args: str) -> tuple[int, str]:
    result = runner.invoke(app, [*args, "--robot", server.new_port()])
    return result.exit_code, result.output


def test_upload_run_pose_delete(
    server: PtyServer, controller: VirtualController, files: tuple[Path, Path]
) -> None:
    program, points = files
    code, out = melfa(server, "upload", str(program), "--points", str(points))
    assert code == 0, out
    assert "uploaded demo.MB4 and 1 points" in out
    stored = controller.store.get("1")
    assert stored is not None
    assert list(stored.lines.values()) == ["10 SERVO ON", "20 MOV P1", "30 HOPEN 1", "40 END"]
    assert list(stored.positions) == ["P1"]
    code, out = melfa(server, "run", "--wait")
    assert (code, out.strip()) == (0, "finished")
    code, out = melfa(server, "pose", "--json")
    assert code == 0, out
    document = json.loads(out)
    assert set(document["pose"]) == {"X", "Y", "Z", "A", "B", "C"}
    assert set(document["joints"]) == {"J1", "J2", "J3", "J4", "J5", "J6"}
    assert document["flags"]["fl1"] == 7
    code, out = melfa(server, "delete")
    assert code == 0 and "1" not in controller.store


def test_text_pose(server: PtyServer) -> None:
    code, out = melfa(server, "pose")
    assert code == 0
    assert out.splitlines()[0].startswith("X ") and "J6" in out.splitlines()[1]


def test_program_with_errors_is_refused_unless_forced(
    server: PtyServer, controller: VirtualController, tmp_path: Path
) -> None:
    bad = tmp_path / "bad.MB4"
    bad.write_text("10 MOV P1\n20 GOTO 99\n30 END\n")
    code, out = melfa(server, "upload", str(bad))
    assert code == 1
    assert "not uploaded" in out and "bad.MB4:" in out
    assert "1" not in controller.store


def test_controller_refusal_exit_1_with_number_and_text(server: PtyServer) -> None:
    assert melfa(server, "servo", "on")[0] == 0
    assert melfa(server, "exec", "JT=(500,0,0,0,0,0)")[0] == 0
    code, out = melfa(server, "exec", "MOV J_CURR+JT")
    assert code == 1
    assert "error 2160" in out and "Joint angle exceeds the limit" in out


def test_exec_hand_servo_stop(server: PtyServer, controller: VirtualController) -> None:
    assert melfa(server, "servo", "on") == (0, "servo on\n")
    assert melfa(server, "hand", "open", "2") == (0, "hand 2 open\n")
    assert melfa(server, "exec", "OVRD 20") == (0, "accepted\n")
    assert melfa(server, "stop") == (0, "stopped\n")
    assert melfa(server, "servo", "off")[0] == 0
    assert not controller.arm.servo


def test_link_failure_exit_3() -> None:
    result = runner.invoke(app, ["stop", "--robot", "/dev/ttyUSB-melfa-missing"])
    assert result.exit_code == 3
    assert "plugged in" in result.output


def test_usage_errors_exit_2(tmp_path: Path) -> None:
    assert runner.invoke(app, ["stop", "--parity", "X"]).exit_code == 2
    assert runner.invoke(app, ["upload", str(tmp_path / "none.MB4")]).exit_code == 2
    assert runner.invoke(app, ["hand", "twist"]).exit_code == 2


def test_default_robot_is_sim(monkeypatch: pytest.MonkeyPatch, files: tuple[Path, Path]) -> None:
    monkeypatch.delenv("MELFA_ROBOT", raising=False)
    program, points = files
    result = runner.invoke(app, ["upload", str(program), "-p", str(points)])
    assert result.exit_code == 0, result.output
    assert "to sim" in result.output


def test_robot_from_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MELFA_ROBOT", "/dev/ttyUSB-melfa-env")
    result = runner.invoke(app, ["stop"])
    assert result.exit_code == 3 and "ttyUSB-melfa-env" in result.output


def test_jog_refuses_without_a_terminal() -> None:
    result = runner.invoke(app, ["jog", "--robot", "sim"])
    assert result.exit_code == 2
    assert "interactive terminal" in result.output


def test_jog_keys_hold_and_release() -> None:
    keys = JogKeys()
    keys.press("w", 0.0)
    assert keys.active(FIRST_REPEAT_S - 0.01) == "w"  # waiting for the first repeat
    keys.press("w", 0.5)  # repeats arrive...
    keys.press("w", 0.53)
    assert keys.active(0.53 + REPEAT_GAP_S - 0.01) == "w"
    assert keys.active(0.53 + REPEAT_GAP_S + 0.01) is None  # ...and stop: released
    keys.press("a", 1.0)
    assert keys.active(1.1) == "a"
