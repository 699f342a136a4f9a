"""Every command block in the README and docs/ runs as written, and where the doc shows
output, the output is what the doc shows.

A block is a fenced ``console`` block (``$ `` starts a command, a line ending in ``\\``
continues it, other lines are its output; a line that is only ``…`` stands for any lines)
or an ``sh`` block (each line a command). Each runs with bash, in a fresh folder holding a
copy of ``examples/``, with ``.venv/bin`` first on PATH, one block's commands in order
(``export`` carries over). A command ending in ``&``, and ``melfa serve``/``melfa sim`` that
serve until stopped, start in the background; the next command runs once they have said
where they listen, and they are stopped (Ctrl-C) when the block ends.

The only things changed from the text: the real arm's ``/dev/ttyUSB0`` is a virtual
controller's address, and the fixed ports 7000/8080 are free ones (another server on this
machine may hold those). Blocks that cannot run here say why in `NOT_RUN`; every other
block runs, so a new block either runs or is named there. The Python examples of
docs/debugger.md run too.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import sys
import urllib.error
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from tests.serving import free_port
from tests.waiting import wait_until

ROOT = Path(__file__).resolve().parents[2]
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BIN = Path(sys.executable).parent

NOT_RUN = {
    ("README.md", "scripts/serve     # the main job"): "sets up .venv; the tests run in it",
    (
        "README.md",
        "scripts/setup --desktop               # .venv with the desktop, and the Debian packages",
    ): "sets up .venv; the desktop is run by tests/desktop/test_xcb.py",
    (
        "desktop.md",
        "scripts/setup --desktop                # as root: also the Debian packages above",
    ): "sets up .venv; the desktop is run by tests/desktop/test_xcb.py",
    (
        "desktop.md",
        ".venv/bin/pytest tests/desktop                 # ~1 min; Qt tests skip without PySide6",
    ): "the desktop tests themselves",
    (
        "ros.md",
        'rosservice call /melfa/state          # "…; alarm 2000: L2000 The servo is OFF; …"',
    ): "needs a ROS 1 master: tests/ros/rospy_tests",
    (
        "debugger.md",
        "melfa debug PROGRAM.MB4 [--points FILE.POS] [--input N=V ...] [--speed "
        "instant|real|xN] [--max-time S]",
    ): "a synopsis (its options in brackets), not a command",
    ("ros.md", "rosparam set --textfile pick.mb4 /melfa/program"): "needs a ROS 1 master",
    ("ros.md", "export ROS_PACKAGE_PATH=$PWD/ros:$ROS_PACKAGE_PATH"): "needs roslaunch",
    (
        "ros.md",
        "roscore &                                        # or your lab's master (ROS_MASTER_URI)",
    ): "needs a ROS 1 master: tests/ros/rospy_tests",
}
"""(file, first command) → why it does not run here."""

SLOW = {"bringup.md"}
"""Files whose blocks run a program on the virtual controller at the lab's speed."""


@dataclass
class Command:
    text: str
    output: list[str] = field(default_factory=list)

    @property
    def background(self) -> bool:
        words = self.text.split("#")[0].split()
        return (
            self.text.rstrip().endswith("&")
            or words[:2] in (["melfa", "serve"],)
            or (words[:2] == ["melfa", "sim"] and "--run" not in words)
        )


@dataclass
class Block:
    file: str
    line: int
    language: str
    text: str

    @property
    def first(self) -> str:
        return self.commands()[0].text.splitlines()[0] if self.commands() else ""

    def commands(self) -> list[Command]:
        found: list[Command] = []
        continuing = False
        for raw in self.text.splitlines():
            line = raw.rstrip()
            if continuing:
                found[-1].text += "\n" + line
            elif self.language == "console" and line.startswith("$ "):
                found.append(Command(line[2:]))
            elif self.language == "sh" and line.strip() and not line.lstrip().startswith("#"):
                found.append(Command(line))
            elif self.language == "console" and found and not re.match(r"\s+#", line):
                found[-1].output.append(line)  # (an indented "# …" is a comment)
            continuing = line.endswith("\\")
        for command in found:
            while command.output and not command.output[-1]:
                command.output.pop()
        return found


def blocks() -> Iterator[Block]:
    fence = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)
    for path in DOCS:
        text = path.read_text(encoding="utf-8")
        for match in fence.finditer(text):
            line = text.count("\n", 0, match.start()) + 1
            yield Block(path.name, line, match.group(1), match.group(2))


def command_blocks() -> list[Block]:
    return [b for b in blocks() if b.language in ("console", "sh")]


def matches(shown: list[str], actual: list[str]) -> bool:
    """Whether ``actual`` is what the doc shows: line by line, ``…`` for any lines, and a
    pty's number for any number."""
    if not shown:
        return not actual
    head, *rest = shown
    if head.strip() == "…":
        return any(matches(rest, actual[i:]) for i in range(len(actual) + 1))
    if not actual:
        return False
    pattern = re.escape(head.rstrip()).replace(r"/dev/pts/7", r"/dev/pts/\d+")
    return bool(re.fullmatch(pattern, actual[0].rstrip())) and matches(rest, actual[1:])


class Runner:
    """Runs one block's commands in order in ``folder``; background servers stopped at the
    end."""

    def __init__(self, folder: Path, robot: str | None) -> None:
        self.folder = folder
        self.robot = robot
        self.env = {k: v for k, v in os.environ.items() if not k.startswith("MELFA_")}
        self.env["PATH"] = f"{BIN}:{self.env.get('PATH', '')}"
        self.env["MELFA_PROFILE"] = str(folder / "profile.json")
        self.env["MELFA_ADMIN_PASSWORD"] = "docs-run-pass-1"
        self.ports = {"7000": str(free_port()), "8080": str(free_port())}
        self.background: list[subprocess.Popen[str]] = []

    def as_run(self, text: str) -> str:
        for written, free in self.ports.items():
            text = re.sub(rf"(?<=[:\s]){written}\b", free, text)
        if self.robot is not None:
            text = text.replace("/dev/ttyUSB0", self.robot)
        return text

    def run(self, command: Command) -> None:
        text = self.as_run(command.text)
        export = re.fullmatch(r"export (\w+)=(\S+)(\s+#.*)?", text.strip())
        if export:
            self.env[export.group(1)] = export.group(2)
            return
        if command.background:
            self.start(text.split("#")[0].rstrip().removesuffix("&"), command)
            return
        done = subprocess.run(
            ["bash", "-c", text],
            cwd=self.folder,
            env=self.env,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,  # as on a terminal: both, in order
            text=True,
            timeout=600,
            check=False,
        )
        said = done.stdout.splitlines()
        errors_shown = any(
            ": error:" in line or line.startswith("error:") for line in command.output
        )
        expected = (0, 1) if errors_shown else (0,)
        assert done.returncode in expected, (command.text, done.returncode, said)
        if command.output:
            assert matches(command.output, said), (command.text, said)

    def start(self, text: str, command: Command) -> None:
        proc = subprocess.Popen(
            ["bash", "-c", f"exec {text}"],
            cwd=self.folder,
            env={**self.env, "PYTHONUNBUFFERED": "1"},
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        self.background.append(proc)
        assert proc.stdout is not None
        said: list[str] = []
        while len(said) < max(1, len(command.output)):
            line = proc.stdout.readline()
            assert line, (command.text, said)
            if line.startswith("Created the first account"):
                continue
            said.append(line.rstrip("\n"))
            listens = "serving on" in line or "listening on" in line
            if listens and len(said) >= len(command.output):
                break
        if command.output:
            assert matches(command.output, said), (command.text, said)
        served = re.search(r"serving on (http://\S+)", "\n".join(said))
        if served:  # up, not only listening: its start-up done before the next command
            wait_until(lambda: answers(served.group(1) + "api/health"), 60, "melfa serve")

    def stop(self) -> None:
        for proc in self.background:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGINT)
            rest, _ = proc.communicate(timeout=60)
            assert "Traceback" not in rest, rest


def answers(url: str) -> bool:
    """Whether an HTTP server answers at ``url`` (a refusal, e.g. of the host name, too)."""
    try:
        with urllib.request.urlopen(url, timeout=2):
            return True
    except urllib.error.HTTPError:
        return True
    except OSError:
        return False


@pytest.fixture
def virtual_robot() -> Iterator[str]:
    """A virtual controller at the lab's line speed, for what the docs send /dev/ttyUSB0."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "melfa", "sim", "--tcp", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    assert proc.stdout is not None
    line = proc.stdout.readline()
    found = re.search(r"tcp://127\.0\.0\.1:\d+", line)
    assert found, line
    yield found.group(0)
    os.killpg(proc.pid, signal.SIGINT)
    proc.communicate(timeout=30)


def test_every_command_block_runs_or_says_why_not() -> None:
    every = {(b.file, b.first) for b in command_blocks()}
    assert len(every) > 15  # the scan found the blocks
    assert set(NOT_RUN) <= every, set(NOT_RUN) - every  # no stale entries


@pytest.mark.parametrize(
    "block",
    [
        pytest.param(b, id=f"{b.file}:{b.line}", marks=[pytest.mark.slow] * (b.file in SLOW))
        for b in command_blocks()
        if (b.file, b.first) not in NOT_RUN
    ],
)
def test_the_block_runs_as_written(block: Block, tmp_path: Path, virtual_robot: str) -> None:
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    runner = Runner(tmp_path, virtual_robot)
    try:
        for command in block.commands():
            runner.run(command)
    finally:
        runner.stop()


def python_blocks() -> list[Block]:
    return [b for b in blocks() if b.language == "python" and b.file == "debugger.md"]


@pytest.mark.parametrize("block", python_blocks(), ids=lambda b: f"{b.file}:{b.line}")
def test_the_debugger_examples_run(block: Block, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)
    exec(compile(block.text, f"{block.file}:{block.line}", "exec"), {})
