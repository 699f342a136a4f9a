"""The command line's conventions, run as a user runs them (a real process, a real terminal
through a pseudo-terminal, real signals): `--version`; `-h` on every command; shell
completion; `NO_COLOR` on a terminal; word on long work; the port `serve` took, and a busy
port refused before anything says "serving"; Ctrl-C ends every command with status 130, one
line and no traceback (from `melfa serve`'s worker processes either)."""

from __future__ import annotations

import json
import os
import re
import shlex
import signal
import socket
import subprocess
import sys
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from importlib.metadata import version
from pathlib import Path

import httpx
import pytest
import typer.main
from typer.testing import CliRunner
from websockets.sync.client import connect

from melfa.cli import EXIT_INTERRUPTED, app
from tests.serving import free_port
from tests.waiting import wait_until

ROOT = Path(__file__).resolve().parents[2]
MELFA = [sys.executable, "-m", "melfa"]
BROKEN = ROOT / "examples" / "broken.MB4"


def clean_env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_DATA")}
    env.pop("NO_COLOR", None)
    env.update(extra)
    return env


def on_a_terminal(args: list[str], env: dict[str, str], cwd: Path = ROOT) -> tuple[int, str]:
    """Run ``melfa ARGS`` with stdout and stderr on a pseudo-terminal; its status and output."""
    main, sub = os.openpty()
    proc = subprocess.Popen([*MELFA, *args], stdout=sub, stderr=sub, env=env, cwd=cwd)
    os.close(sub)
    chunks: list[bytes] = []
    while True:
        try:
            chunk = os.read(main, 65536)
        except OSError:  # EIO: the process closed the terminal
            break
        if not chunk:
            break
        chunks.append(chunk)
    os.close(main)
    return proc.wait(timeout=120), b"".join(chunks).decode("utf-8", "replace")


def test_version_is_the_installed_packages() -> None:
    done = subprocess.run(
        [*MELFA, "--version"], capture_output=True, text=True, env=clean_env(), check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == f"melfa {version('melfa')}"


def test_a_usage_mistake_is_one_message_and_status_2_never_a_traceback() -> None:
    for words in (["debug", "X.MB4", "extra"], ["serve", "--port", "high"], ["no-such"]):
        done = subprocess.run(
            [*MELFA, *words], capture_output=True, text=True, env=clean_env(), check=False
        )
        assert done.returncode == 2, (words, done.stderr)
        assert "Traceback" not in done.stderr and "Error" in done.stderr, (words, done.stderr)


def commands(group: object, prefix: tuple[str, ...] = ()) -> Iterator[tuple[str, ...]]:
    for name, command in getattr(group, "commands", {}).items():
        yield (*prefix, name)
        yield from commands(command, (*prefix, name))


def test_dash_h_works_on_every_command() -> None:
    root = typer.main.get_command(app)
    every = [(), *commands(root)]
    assert len(every) > 20  # the walk found the commands and the groups' subcommands
    runner = CliRunner()
    for words in every:
        result = runner.invoke(app, [*words, "-h"])
        assert result.exit_code == 0, (words, result.output)
        assert "Usage" in result.output or "usage" in result.output, (words, result.output)


def test_shell_completion_is_offered_and_answers() -> None:
    # Typed in the user's bash: typer finds the shell among the command's parents (a suite
    # started in the background may have none of its own).
    script = subprocess.run(
        ["bash", "-c", f"{shlex.join(MELFA)} --show-completion; exit $?"],
        capture_output=True,
        text=True,
        env=clean_env(),
        check=False,
    )
    assert script.returncode == 0, script.stderr
    assert "_MELFA_COMPLETE" in script.stdout and "complete " in script.stdout
    # What bash asks when the user types `melfa ser<Tab>` and `melfa users a<Tab>`.
    for words, cword, expected in (("melfa ser", "1", "serve"), ("melfa users a", "2", "add")):
        env = clean_env(_MELFA_COMPLETE="complete_bash", COMP_WORDS=words, COMP_CWORD=cword)
        answer = subprocess.run(MELFA, capture_output=True, text=True, env=env, check=False)
        assert expected in answer.stdout.split(), (words, answer.stdout, answer.stderr)


def test_check_honours_no_color_on_a_terminal() -> None:
    status, coloured = on_a_terminal(["check", str(BROKEN)], clean_env())
    assert status == 1 and "\x1b[" in coloured  # a terminal: colours by default
    status, plain = on_a_terminal(["check", str(BROKEN)], clean_env(NO_COLOR="1"))
    assert status == 1
    assert "\x1b[" not in plain, plain
    assert "error: WIHLE is not a MELFA BASIC IV word" in plain
    assert "    2 | WIHLE" in plain  # still the source excerpt a terminal gets
    for env in (clean_env(), clean_env(NO_COLOR="1")):  # the other commands' messages too
        status, said = on_a_terminal(["fmt", "no-such.MB4"], env)
        assert status == 2 and "no-such.MB4" in said
        assert ("\x1b[" in said) is ("NO_COLOR" not in env), said


def test_check_says_what_it_checks_when_that_takes_long(tmp_path: Path) -> None:
    big = tmp_path / "big.MB4"
    big.write_text("".join(f"M1 = M1 + {n}  ' one more\n" for n in range(1, 20_000)))
    assert big.stat().st_size > 300_000
    status, shown = on_a_terminal(["check", str(big)], clean_env())
    assert status == 0, shown
    assert f"checking big.MB4 ({big.stat().st_size / 1e6:.1f} MB)…" in shown
    piped = subprocess.run(
        [*MELFA, "check", str(big)], capture_output=True, text=True, env=clean_env(), check=False
    )
    assert "checking" not in piped.stderr + piped.stdout  # nothing extra in a pipe


def served_port(proc: subprocess.Popen[str]) -> tuple[int, list[str]]:
    """The port in `melfa serve`'s "serving on" line, and the lines before it."""
    seen: list[str] = []
    assert proc.stdout is not None
    for line in proc.stdout:
        seen.append(line)
        found = re.search(r"serving on http://127\.0\.0\.1:(\d+)/", line)
        if found:
            return int(found.group(1)), seen
    raise AssertionError(f"no 'serving on' line: {seen}")


LOOPING = "SERVO ON\n*LOOP\nMOV P1\nMOV P2\nGOTO *LOOP\nEND\n"
LOOPING_POINTS = (
    "DEF POS P1=(350.00,-150.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,150.00,300.00,180.00,0.00,180.00)(7,0)\n"
)
SERVE_PASSWORD = "conventions-pass-1"


@contextmanager
def serving(tmp_path: Path, *options: str) -> Iterator[tuple[subprocess.Popen[str], str]]:
    """`melfa serve --port 0` as a terminal's foreground job (its own process group) and
    its address; ended with Ctrl-C if the test did not end it."""
    proc = subprocess.Popen(
        [*MELFA, "serve", *options, "--port", "0", "--data", str(tmp_path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=clean_env(MELFA_ADMIN_PASSWORD=SERVE_PASSWORD),
        start_new_session=True,
    )
    try:
        port, _ = served_port(proc)
        assert port != 0
        yield proc, f"http://127.0.0.1:{port}"
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
            proc.communicate(timeout=60)


def run_looping(client: httpx.Client, target: dict[str, str]) -> None:
    """Signed in as the admin, a looping program run on ``target`` until it runs."""
    signed = client.post("/api/session", json={"username": "admin", "password": SERVE_PASSWORD})
    signed.raise_for_status()
    client.headers["X-CSRF-Token"] = signed.json()["csrf_token"]
    if not target:
        client.post("/api/lease").raise_for_status()
    for path, body in (
        ("/api/robot/servo", {"on": True}),
        ("/api/robot/project", {"program": LOOPING, "points": LOOPING_POINTS}),
        ("/api/robot/run", None),
    ):
        client.post(path, json=body, params=target).raise_for_status()
    state = "/api/robot/state"
    wait_until(lambda: client.get(state, params=target).json()["running"], 60, "the run")


def ctrl_c(proc: subprocess.Popen[str]) -> None:
    """Ctrl-C as a terminal sends it (the whole group, workers too): status 130, "melfa
    stopped", no traceback."""
    os.killpg(proc.pid, signal.SIGINT)
    rest, _ = proc.communicate(timeout=60)
    assert proc.returncode == EXIT_INTERRUPTED, rest
    assert "Traceback" not in rest and "KeyboardInterrupt" not in rest, rest
    assert "melfa stopped" in rest


def test_serve_port_0_prints_the_port_taken_and_ctrl_c_ends_it_with_130(tmp_path: Path) -> None:
    """With a browser's socket open on a private simulator that runs a program (a lab's
    usual moment to stop the server): Ctrl-C still ends it with 130, cleanly."""
    with serving(tmp_path) as (proc, base):

        def answers() -> bool:
            try:
                with urllib.request.urlopen(f"{base}/api/health", timeout=2):
                    return True
            except OSError:
                return False

        wait_until(answers, 60, "the served port to answer")
        with httpx.Client(base_url=base, timeout=60) as client:
            run_looping(client, {"target": "mine"})
            cookie = f"melfa_session={client.cookies['melfa_session']}"
        with connect(
            base.replace("http:", "ws:") + "/api/ws?target=mine",
            additional_headers={"Cookie": cookie, "Origin": base},
        ) as ws:
            wait_until(lambda: '"running":true' in str(ws.recv(timeout=60)), 60, "state")
            ctrl_c(proc)


def test_ctrl_c_with_a_rosbridge_client_subscribed_ends_with_130(tmp_path: Path) -> None:
    """The rosbridge server ends inside the web server's shutdown: cut off by the re-raised
    Ctrl-C instead, its sockets' tasks printed tracebacks."""
    bridge = free_port()
    with serving(tmp_path, "--rosbridge-port", str(bridge)) as (proc, base):
        with httpx.Client(base_url=base, timeout=60) as client:
            wait_until(lambda: client.get("/api/health").status_code == 200, 60, "health")
            run_looping(client, {})
            token = client.cookies["melfa_session"]
        with connect(f"ws://127.0.0.1:{bridge}/rosbridge") as ros:
            ros.send(json.dumps({"op": "auth", "mac": token}))
            ros.send(json.dumps({"op": "subscribe", "topic": "/joint_states"}))
            assert '"topic": "/joint_states"' in str(ros.recv(timeout=60))
            ctrl_c(proc)


def test_serve_on_a_busy_port_fails_before_saying_serving(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        done = subprocess.run(
            [*MELFA, "serve", "--port", str(port), "--data", str(tmp_path)],
            capture_output=True,
            text=True,
            env=clean_env(MELFA_ADMIN_PASSWORD="conventions-pass-1"),
            timeout=120,
            check=False,
        )
    assert done.returncode == 2
    assert f"port {port} on 127.0.0.1 is in use" in done.stderr
    assert "serving on" not in done.stdout
    assert "Traceback" not in done.stderr


@pytest.fixture
def sim_tcp(tmp_path: Path) -> Iterator[str]:
    """A persistent virtual controller (`melfa sim --tcp`) for `upload` then `run`."""
    port = free_port()
    proc = subprocess.Popen(
        [*MELFA, "sim", "--tcp", f"127.0.0.1:{port}"],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=clean_env(),
        start_new_session=True,
    )
    try:

        def listening() -> bool:
            assert proc.poll() is None
            with socket.socket() as probe:
                return probe.connect_ex(("127.0.0.1", port)) == 0

        wait_until(listening, 60, "the virtual controller to listen")
        yield f"tcp://127.0.0.1:{port}"
    finally:
        os.killpg(proc.pid, signal.SIGINT)
        rest, _ = proc.communicate(timeout=30)
    assert proc.returncode == EXIT_INTERRUPTED, rest  # `melfa sim` keeps the convention too
    assert "Traceback" not in rest and "virtual controller stopped" in rest


def test_ctrl_c_on_serve_stops_a_program_nobody_watches(sim_tcp: str, tmp_path: Path) -> None:
    """Ctrl-C: whatever was moving is stopped first, by `melfa serve` too. A program run
    through the API with no socket open (a script's) ran on after the server had gone,
    with no STOP button left anywhere in the IDE."""
    with serving(tmp_path, "--robot", sim_tcp) as (proc, base):
        with httpx.Client(base_url=base, timeout=60) as client:

            def linked() -> bool:
                return bool(client.get("/api/health").json()["robot"]["link"] == "connected")

            wait_until(linked, 60, "the robot link")
            run_looping(client, {})
        ctrl_c(proc)
    status = subprocess.run(
        [*MELFA, "status", "--json"],
        capture_output=True,
        text=True,
        env=clean_env(MELFA_ROBOT=sim_tcp),
        check=False,
    )
    assert '"run": "stopped"' in status.stdout, status.stdout


def test_run_wait_shows_its_line_and_ctrl_c_stops_the_robot(sim_tcp: str, tmp_path: Path) -> None:
    program = tmp_path / "loop.MB4"
    program.write_text("10 SERVO ON\n20 *LOOP\n30 MOV P1\n40 MOV P2\n50 GOTO *LOOP\n")
    points = tmp_path / "loop.POS"
    points.write_text(
        "P1=(400.00,0.00,600.00,180.00,0.00,180.00)(7,0)\n"
        "P2=(300.00,100.00,500.00,180.00,0.00,180.00)(7,0)\n"
    )
    env = clean_env(MELFA_ROBOT=sim_tcp)
    upload = subprocess.run(
        [*MELFA, "upload", str(program), "--points", str(points)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
        check=False,
    )
    assert upload.returncode == 0, upload.stdout + upload.stderr
    main, sub = os.openpty()
    proc = subprocess.Popen(
        [*MELFA, "run", "--wait"], stdout=sub, stderr=sub, env=env, start_new_session=True
    )
    os.close(sub)
    shown = b""
    try:
        while not re.search(rb"running line [34]0", shown):  # the program's moves, live
            chunk = os.read(main, 4096)
            assert chunk, shown
            shown += chunk
    finally:
        os.killpg(proc.pid, signal.SIGINT)
    while True:
        try:
            chunk = os.read(main, 4096)
        except OSError:
            break
        if not chunk:
            break
        shown += chunk
    os.close(main)
    assert proc.wait(timeout=60) == EXIT_INTERRUPTED
    text = shown.decode("utf-8", "replace")
    assert "interrupted: robot stopped" in text
    assert "Traceback" not in text
    status = subprocess.run(
        [*MELFA, "status", "--json"], capture_output=True, text=True, env=env, check=False
    )
    assert '"run": "stopped"' in status.stdout, status.stdout
