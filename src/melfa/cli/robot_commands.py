"""`melfa upload|run|stop|delete|exec|pose|hand|servo|jog`: drive a controller.

Thin: parse options, call `melfa.robot`, print. Every command takes ``--robot`` (a serial
device such as ``/dev/ttyUSB0``, ``tcp://host:port``, a pyserial URL such as
``socket://host:port`` or ``rfc2217://…``, or ``sim``; default ``$MELFA_ROBOT``, else
``sim``) and the line settings (``--baud``, ``--parity``, ``--stopbits``: 9600 8E2 by default).

``--robot sim`` starts a fresh in-process virtual controller for each invocation, so an
``upload`` followed by a separate ``run`` only makes sense against a persistent simulator:
start ``melfa sim --tcp 127.0.0.1:7000`` (or ``--pty``) and pass its address.

Exit codes: 0 done, 1 refused (by the controller, or errors in the program), 2 usage,
3 link failure or timeout.
"""

from __future__ import annotations

import contextlib
import enum
import json
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.progress import (
    BarColumn,
    DownloadColumn,
    Progress,
    TextColumn,
    TimeRemainingColumn,
)

from melfa.cli.app import app
from melfa.link import (
    DEFAULT_TIMEOUT_S,
    ROBOT_ENV,
    SIM_SPEC,
    LinkError,
    LinkSettings,
)
from melfa.protocol import (
    JOINT_NAMES,
    POSE_NAMES,
    JogMode,
    LocalProtocolError,
    RemoteProtocolError,
)
from melfa.robot import ControllerError, Robot, RobotError, Stopped, UploadRefused

EXIT_REFUSED = 1
EXIT_USAGE = 2
EXIT_LINK = 3

_out = Console(highlight=False, soft_wrap=True, emoji=False)
_err = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)


def _fail(message: str, code: int) -> typer.Exit:
    _err.print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(code)


# --- shared options ----------------------------------------------------------------------

RobotOpt = Annotated[
    str | None,
    typer.Option(
        "--robot",
        "-r",
        envvar=ROBOT_ENV,
        show_default=False,
        metavar="ROBOT",
        help="Serial device (/dev/ttyUSB0), tcp://host:port, a pyserial URL (socket://, "
        "rfc2217://, loop://) or 'sim' (a fresh in-process simulator each run). "
        f"Default: ${ROBOT_ENV}, else sim.",
    ),
]
BaudOpt = Annotated[int, typer.Option("--baud", help="Baud rate (controller CBAU232).")]
ParityOpt = Annotated[str, typer.Option("--parity", help="Parity N, E or O (controller CPRTY232).")]
StopbitsOpt = Annotated[int, typer.Option("--stopbits", help="Stop bits 1 or 2 (CSTOP232).")]
TimeoutOpt = Annotated[
    float, typer.Option("--timeout", metavar="S", help="Seconds to wait for each reply.")
]
TraceOpt = Annotated[
    bool,
    typer.Option("--trace", help="Print every byte sent and received to stderr (MELFA_TRACE=1)."),
]


@dataclass(frozen=True)
class Target:
    """Where and how to connect, from the shared options."""

    spec: str
    settings: LinkSettings
    trace: bool | None


def _target(
    robot: str | None, baud: int, parity: str, stopbits: int, timeout: float, trace: bool
) -> Target:
    try:
        settings = LinkSettings(
            baudrate=baud, parity=parity.upper(), stopbits=stopbits, timeout=timeout
        )
    except ValueError as exc:
        raise _fail(str(exc), EXIT_USAGE) from None
    return Target((robot or "").strip() or SIM_SPEC, settings, True if trace else None)


@contextlib.contextmanager
def _session(target: Target) -> Iterator[Robot]:
    """Open the robot and turn every failure into one message and its exit code."""
    robot: Robot | None = None
    try:
        robot = Robot.open(target.spec, target.settings, trace=target.trace)
        yield robot
    except UploadRefused as exc:
        _err.print(f"[bold red]refused:[/] {escape(str(exc))}")
        raise typer.Exit(EXIT_REFUSED) from None
    except ControllerError as exc:
        raise _fail(
            f"controller refused{f' {exc.command}' if exc.command else ''}: "
            f"error {exc.number:04d} {exc.message}",
            EXIT_REFUSED,
        ) from None
    except Stopped as exc:
        raise _fail(str(exc), EXIT_REFUSED) from None
    except LinkError as exc:
        raise _fail(f"link to {target.spec}: {exc}", EXIT_LINK) from None
    except RemoteProtocolError as exc:
        raise _fail(f"garbled reply from {target.spec}: {exc}", EXIT_LINK) from None
    except (LocalProtocolError, RobotError) as exc:
        raise _fail(str(exc), EXIT_USAGE) from None
    finally:
        if robot is not None:
            robot.close()


# --- upload ------------------------------------------------------------------------------


def _read_text(path: Path, what: str) -> tuple[str, object]:
    from melfa.cli.lang_commands import FileKind, UsageError, read_source

    kind = FileKind.POINTS if what == "points" else FileKind.PROGRAM
    try:
        source = read_source(path, kind)
    except UsageError as exc:
        raise _fail(str(exc), EXIT_USAGE) from None
    if not source.is_text:
        raise _fail(f"{path}: not a text file", EXIT_USAGE)
    return source.text, source


@app.command(
    help="Check, number and upload a program (and its points) as program 1 in slot 1.\n\n"
    "Program and points go in one LOAD…SAVE session; nothing is saved unless every line "
    "was accepted. With --robot sim the upload goes to a throw-away simulator: start "
    "`melfa sim --tcp 127.0.0.1:7000` (or --pty) for one that persists between commands."
)
def upload(
    program: Annotated[Path, typer.Argument(help="MELFA BASIC IV program (.MB4).")],
    points: Annotated[
        Path | None, typer.Option("--points", "-p", help="Points file (.POS) to send too.")
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Upload even if the checker finds errors.")
    ] = False,
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """See the help text above."""
    from melfa.cli.lang_commands import check_files, print_text
    from melfa.lang.diagnostics import Severity
    from melfa.lang.numbering import NumberingError, number_lines
    from melfa.lang.points import parse_points, upload_lines

    target = _target(robot, baud, parity, stopbits, timeout, trace)
    text, program_source = _read_text(program, "program")
    sources = [program_source]
    point_lines: list[str] = []
    if points is not None:
        points_text, points_source = _read_text(points, "points")
        sources.append(points_source)
        point_lines = upload_lines(parse_points(points_text).points)
    reports = check_files(sources)  # type: ignore[arg-type]
    errors = [d for r in reports for d in r.diagnostics if d.severity is Severity.ERROR]
    if errors and not force:
        print_text(reports, _err)
        raise _fail(
            f"{program}: not uploaded because of the errors above (--force to upload anyway)",
            EXIT_REFUSED,
        )
    numbered = all(line.strip()[:1].isdigit() for line in text.splitlines() if line.strip())
    if not numbered:
        try:
            text = number_lines(text)
        except NumberingError as exc:
            raise _fail(f"{program}: cannot number the lines: {exc}", EXIT_REFUSED) from None

    with _session(target) as session, _progress() as bar:
        task = bar.add_task(f"upload {program.name}", total=None)

        def progress(sent: int, total: int) -> None:
            bar.update(task, completed=sent, total=total)

        report = session.load_project(text, point_lines, progress=progress)
    _out.print(
        f"uploaded {program.name}"
        + (f" and {len(point_lines)} points" if points is not None else "")
        + f" to {target.spec}: {report.items} items in {report.requests} EMDAT requests, "
        f"{report.bytes_sent} bytes, {report.seconds:.1f} s"
    )


def _progress() -> Progress:
    return Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        DownloadColumn(binary_units=False),
        TimeRemainingColumn(),
        console=_err,
        transient=True,
        disable=not _err.is_terminal,
    )


# --- simple commands ---------------------------------------------------------------------


@app.command()
def run(
    wait: Annotated[
        bool, typer.Option("--wait/--no-wait", help="Wait until the program has finished.")
    ] = False,
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Start program 1 in slot 1 once (cycle mode); needs a persistent robot, not sim."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.run()
        if wait:
            try:
                session.wait_idle(timeout=3600)
            except KeyboardInterrupt:
                session.stop()
                raise _fail("interrupted: robot stopped", EXIT_REFUSED) from None
    _out.print("finished" if wait else "started")


@app.command()
def stop(
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Stop every slot and any motion now (needs no operation rights)."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.stop()
    _out.print("stopped")


@app.command()
def delete(
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Delete program 1 and its points from the controller."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.delete()
    _out.print("deleted")


@app.command("exec")
def exec_(
    statement: Annotated[str, typer.Argument(help='One statement, e.g. "MOV P1" or "OVRD 20".')],
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Execute one MELFA BASIC statement now (replies when accepted, not when done)."""
    if not statement.strip():
        raise _fail("empty statement", EXIT_USAGE)
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.exec(statement)
    _out.print("accepted")


@app.command()
def pose(
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Show the tool pose (X Y Z mm, A B C deg, flags) and the joints J1–J6 (deg)."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        tool = session.pose()
        joints = session.joints()
        values = dict(zip(POSE_NAMES, tool.values(*POSE_NAMES), strict=True))
        angles = dict(zip(JOINT_NAMES, joints.values(*JOINT_NAMES), strict=True))
    if as_json:
        document = {
            "pose": values,
            "flags": {"fl1": tool.fl1, "fl2": tool.fl2},
            "joints": angles,
            "override": tool.override,
            "speed": tool.speed,
        }
        _out.print_json(json.dumps(document))
        return
    _out.print("  ".join(f"{k} {v:9.2f}" for k, v in values.items()) + f"  ({tool.fl1},{tool.fl2})")
    _out.print("  ".join(f"{k} {v:8.2f}" for k, v in angles.items()))


class HandAction(enum.StrEnum):
    OPEN = "open"
    CLOSE = "close"


@app.command()
def hand(
    action: Annotated[HandAction, typer.Argument(help="open or close.")],
    number: Annotated[int, typer.Argument(min=1, max=8, help="Hand number 1–8.")] = 1,
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Open or close a hand (EXECHOPEN n / EXECHCLOSE n)."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.hand(action is HandAction.OPEN, number)
    _out.print(f"hand {number} {action.value}")


class OnOff(enum.StrEnum):
    ON = "on"
    OFF = "off"


@app.command()
def servo(
    state: Annotated[OnOff, typer.Argument(help="on or off.")],
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """Switch the servo power on (needs the operation rights) or off."""
    target = _target(robot, baud, parity, stopbits, timeout, trace)
    with _session(target) as session:
        session.servo(state is OnOff.ON)
    _out.print(f"servo {state.value}")


# --- jog ---------------------------------------------------------------------------------

JOG_KEYS: dict[str, tuple[int, int]] = {
    "w": (0, +1),  # +X
    "s": (0, -1),  # -X
    "a": (1, +1),  # +Y
    "d": (1, -1),  # -Y
    "UP": (2, +1),  # +Z
    "DOWN": (2, -1),  # -Z
}
"""The thesis's keys: w/s ±X, a/d ±Y, up/down ±Z; space toggles the hand, q quits."""

FIRST_REPEAT_S = 0.6
"""A terminal repeats a held key only after a delay (typically 250–600 ms)."""
REPEAT_GAP_S = 0.2
"""Between repeats (typically 30–100 ms): no key for this long after a repeat = released."""
JOG_PERIOD_S = 0.1
"""JOG is re-sent this often while a key is held (controller watchdog ~140 ms [DOC S1])."""


class JogKeys:
    """Turns key events (with repeats) into hold-to-move: which jog is active at time t.

    >>> keys = JogKeys()
    >>> keys.press("w", 0.0); keys.active(0.5)
    'w'
    >>> keys.press("w", 0.55); keys.active(0.7), keys.active(0.8)
    ('w', None)
    """

    def __init__(self) -> None:
        self.key: str | None = None
        self.until = 0.0

    def press(self, key: str, now: float) -> None:
        """A key event; a repeat of the active key extends the hold briefly."""
        repeat = key == self.key and now <= self.until
        self.key = key
        self.until = now + (REPEAT_GAP_S if repeat else FIRST_REPEAT_S)

    def active(self, now: float) -> str | None:
        """The held key, or None once its repeats have stopped."""
        if self.key is not None and now > self.until:
            self.key = None
        return self.key

    def release(self) -> None:
        """Forget the held key (another key was pressed)."""
        self.key = None


def _read_keys(timeout: float) -> list[str]:
    import os
    import select

    fd = sys.stdin.fileno()
    ready, _, _ = select.select([fd], [], [], timeout)
    if not ready:
        return []
    data = os.read(fd, 64).decode("latin-1")
    keys: list[str] = []
    i = 0
    while i < len(data):
        if data.startswith("\x1b[A", i) or data.startswith("\x1bOA", i):
            keys.append("UP")
            i += 3
        elif data.startswith("\x1b[B", i) or data.startswith("\x1bOB", i):
            keys.append("DOWN")
            i += 3
        else:
            keys.append(data[i].lower() if data[i] != " " else "SPACE")
            i += 1
    return keys


@app.command(
    help="Jog from the keyboard: hold w/s (±X), a/d (±Y), up/down (±Z); space toggles the "
    "hand; q quits. The arm moves only while a key is held. Needs an interactive terminal."
)
def jog(
    override: Annotated[
        int, typer.Option("--override", min=1, max=100, help="Jog speed override, %.")
    ] = 10,
    hand_number: Annotated[int, typer.Option("--hand", min=1, max=8, help="Hand for space.")] = 1,
    robot: RobotOpt = None,
    baud: BaudOpt = 9600,
    parity: ParityOpt = "E",
    stopbits: StopbitsOpt = 2,
    timeout: TimeoutOpt = DEFAULT_TIMEOUT_S,
    trace: TraceOpt = False,
) -> None:
    """See the help text above."""
    if not sys.stdin.isatty():
        raise _fail("melfa jog needs an interactive terminal (stdin is not a TTY)", EXIT_USAGE)
    import termios
    import tty

    target = _target(robot, baud, parity, stopbits, timeout, trace)
    fd = sys.stdin.fileno()
    saved = termios.tcgetattr(fd)
    _out.print("w/s ±X  a/d ±Y  ↑/↓ ±Z  space hand  q quit")
    with _session(target) as session:
        session.servo(True)
        session.override(override)
        keys = JogKeys()
        hand_open = False
        moving: str | None = None
        try:
            tty.setcbreak(fd)
            next_send = 0.0
            while True:
                for key in _read_keys(JOG_PERIOD_S / 2):
                    now = time.monotonic()
                    if key == "q":
                        return
                    if key == "SPACE":
                        hand_open = not hand_open
                        session.hand(hand_open, hand_number)
                    elif key in JOG_KEYS:
                        if key != keys.key:
                            keys.release()
                        keys.press(key, now)
                now = time.monotonic()
                held = keys.active(now)
                if held is None and moving is not None:
                    session.jog_stop()
                    moving = None
                elif held is not None and (held != moving or now >= next_send):
                    axis, direction = JOG_KEYS[held]
                    session.jog(JogMode.XYZ, axis, direction)
                    moving, next_send = held, now + JOG_PERIOD_S
        finally:
            termios.tcsetattr(fd, termios.TCSADRAIN, saved)
            if moving is not None:
                with contextlib.suppress(Exception):
                    session.jog_stop()
