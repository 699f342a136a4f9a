"""`melfa upload|run|stop|…` in process (CliRunner) against a persistent simulator on a
fresh pty per invocation, opened at 9600 8E2 like a real port."""

from __future__ import annotations

import json
import os
import socket
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

import melfa.cli.robot_commands
from melfa.cli.robot_commands import FIRST_REPEAT_S, REPEAT_GAP_S, JogKeys
from melfa.cli.typer_app import app
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
    assert out.startswith(
        "error: the controller refused `MOV J_CURR+JT`: H2160 Joint angle exceeds the limit"
    )


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


# ---------------------------------------------------------------------------------------
# The student's flow, alarms, and what the messages say

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TOO_FAR = "MOV P_CURR*(0,0,-5000,0,0,0)"
SIM_SPEEDUP = 200.0
"""The flow test runs the simulator's clock this much faster than real time."""


def test_accents_in_comments_and_strings_are_sent_as_plain_letters(
    server: PtyServer, controller: VirtualController, tmp_path: Path
) -> None:
    source = "' Piràmide\nSERVO ON\nPRINT \"peça\"\nMOV P1   ' repòs\nEND\n"
    program = tmp_path / "accents.MB4"
    program.write_bytes(source.encode("utf-8"))
    points = tmp_path / "accents.POS"
    points.write_text("' Punts de la piràmide\n" + POINTS, encoding="utf-8")
    code, out = melfa(server, "upload", str(program), "--points", str(points))
    assert code == 0, out
    assert (
        "note: accents.MB4: comments and strings on lines 1, 3, 4 sent without accents; "
        "your file is unchanged" in out
    )
    stored = controller.store.get("1")
    assert stored is not None
    assert list(stored.lines.values()) == [
        "10 ' Piramide",
        "20 SERVO ON",
        '30 PRINT "peca"',
        "40 MOV P1   ' repos",
        "50 END",
    ]
    assert list(stored.positions) == ["P1"]
    assert program.read_bytes() == source.encode("utf-8")


def test_non_ascii_code_is_refused_before_sending_even_with_force(
    server: PtyServer, controller: VirtualController, tmp_path: Path
) -> None:
    program = tmp_path / "name.MB4"
    program.write_text("MPEÇA = 1\nEND\n", encoding="utf-8")
    code, out = melfa(server, "upload", str(program), "--force")
    assert code == 1
    assert f"{program}:1:4: 'Ç' is not ASCII and is not in a comment or string" in out
    assert "1" not in controller.store


def test_student_flow_with_the_pyramid_example() -> None:
    """upload → servo on → run --wait → pose → status, as a student does it."""
    controller = VirtualController()
    with PtyServer(controller, clock=lambda: time.monotonic() * SIM_SPEEDUP) as server:
        code, out = melfa(
            server,
            "upload",
            str(EXAMPLES / "pyramid.MB4"),
            "--points",
            str(EXAMPLES / "pyramid.POS"),
        )
        assert code == 0, out
        assert "note: pyramid.MB4: comments on lines 1, 2, 3, 6" in out
        assert "uploaded pyramid.MB4 and 4 points" in out
        assert melfa(server, "servo", "on") == (0, "servo on\n")
        assert not controller.arm.hand_open(1)
        code, out = melfa(server, "run", "--wait")
        assert (code, out) == (0, "finished\n")
        code, out = melfa(server, "pose", "--json")
        assert code == 0, out
        joints = json.loads(out)["joints"]
        assert [round(joints[n], 2) for n in ("J1", "J2", "J3", "J4", "J5", "J6")] == [
            0.0,
            0.0,
            90.0,
            0.0,
            90.0,
            0.0,
        ]  # MOV Jsafe, the program's last move
        assert controller.arm.hand_open(1)  # the last piece was let go
        code, out = melfa(server, "status", "--json")
        assert code == 0, out
        status = json.loads(out)
        assert (status["run"], status["alarm"], status["servo"]) == ("stopped", None, True)
        assert controller.store.get("1") is not None
        # [TRACE K9b-PROG] after a cycle run ends STATE names no program and line 0.
        assert (status["program"], status["line"]) == (None, 0)


def test_alarm_hint_status_and_reset(server: PtyServer) -> None:
    assert melfa(server, "servo", "on")[0] == 0
    code, out = melfa(server, "exec", TOO_FAR)
    assert code == 1
    assert out.splitlines() == [
        f"error: the controller refused `{TOO_FAR}`: L2600 Position data exceeds the limit",
        "An alarm is active (L2600 Position data exceeds the limit): clear it with `melfa reset`.",
    ]
    code, out = melfa(server, "exec", "OVRD 10")
    assert code == 1
    assert "L5600 Cannot execute during an error" in out
    assert out.rstrip().endswith(
        "An alarm is active (L2600 Position data exceeds the limit): clear it with `melfa reset`."
    )
    code, out = melfa(server, "status")
    assert code == 0
    assert "alarm     L2600 Position data exceeds the limit (clear it with `melfa reset`)" in out
    assert "servo     on" in out
    assert melfa(server, "reset") == (0, "cleared L2600 Position data exceeds the limit\n")
    assert melfa(server, "reset") == (0, "no alarm was active\n")
    code, out = melfa(server, "status")
    assert "alarm     none" in out
    assert melfa(server, "exec", "OVRD 10") == (0, "accepted\n")


def test_refusal_without_alarm_has_no_hint(server: PtyServer) -> None:
    code, out = melfa(server, "run")  # nothing uploaded
    assert code == 1
    assert out == "error: the controller refused `RUN1;1`: L4140 The program was not found\n"


def test_run_wait_reports_a_program_that_stops_on_an_error(
    server: PtyServer, tmp_path: Path
) -> None:
    program = tmp_path / "far.MB4"
    program.write_text(f"SERVO ON\n{TOO_FAR}\nEND\n")
    assert melfa(server, "upload", str(program))[0] == 0
    code, out = melfa(server, "run", "--wait")
    assert code == 1
    assert out.splitlines() == [
        "error: the program stopped at line 20: L2600 Position data exceeds the limit",
        "An alarm is active (L2600 Position data exceeds the limit): clear it with `melfa reset`.",
    ]


def test_link_failures_name_the_port_and_what_to_check(tmp_path: Path) -> None:
    master, slave = os.openpty()  # a port where nothing ever answers
    try:
        port = os.ttyname(slave)
        result = runner.invoke(app, ["stop", "--robot", port, "--timeout", "0.3"])
    finally:
        os.close(master)
        os.close(slave)
    assert result.exit_code == 3
    assert f"no answer from {port}" in result.output
    assert "Check the cable" in result.output
    assert "--baud 9600 --parity E --stopbits 2" in result.output

    with socket.socket() as probe:  # a free port: nobody listens there
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
    result = runner.invoke(app, ["stop", "--robot", address])
    assert result.exit_code == 3
    assert f"the link to {address} failed" in result.output
    assert "melfa sim --tcp" in result.output


def test_help_explains_sim_and_jog_keys() -> None:
    result = runner.invoke(app, ["upload", "--help"], env={"COLUMNS": "200"})
    assert "throw-away simulator" in result.output
    result = runner.invoke(app, ["jog", "--robot", "sim"])
    assert result.exit_code == 2
    assert "needs an interactive terminal" in result.output and "melfa exec" in result.output


def test_run_on_the_throw_away_simulator_explains_why_nothing_is_there(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.delenv("MELFA_ROBOT", raising=False)
    result = runner.invoke(app, ["run"])
    assert result.exit_code == 1
    assert "L4140 The program was not found" in result.output
    assert "--robot sim is a throw-away simulator" in result.output
