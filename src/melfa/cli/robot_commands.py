"""`melfa upload|run|stop|delete|exec|pose|hand|servo|reset|status|jog`: drive a controller.

Thin: parse options, call `melfa.robot`, print. Every command takes ``--robot`` (a serial
device such as ``/dev/ttyUSB0``, ``tcp://host:port``, a pyserial URL such as
``socket://host:port`` or ``rfc2217://…``, or ``sim``; default ``$MELFA_ROBOT``, else
``sim``) and the line settings (``--baud``, ``--parity``, ``--stopbits``: 9600 8E2 by default).

``--robot sim`` starts a throw-away in-process virtual controller for each invocation, so an
``upload`` followed by a separate ``run`` only makes sense against a persistent simulator:
start ``melfa sim --tcp 127.0.0.1:7000`` (or ``--pty``) and pass its address.

Refusals read like ``error: the controller refused `MOV P1`: L2600 Position data exceeds the
limit``; while an alarm is active they end with how to clear it (``melfa reset``).

Exit codes: 0 done, 1 refused (by the controller, or errors in the program), 2 usage,
3 link failure or timeout.
"""

from __future__ import annotations

import contextlib
import enum
import functools
import inspect
import json
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

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

from melfa.cli.typer_app import app
from melfa.link import (
    DEFAULT_TIMEOUT_S,
    ROBOT_ENV,
    SIM_SPEC,
    LinkError,
    LinkSettings,
    LinkTimeout,
)
from melfa.protocol import (
    JOINT_NAMES,
    POSE_NAMES,
    JogMode,
    LocalProtocolError,
    RemoteProtocolError,
)
from melfa.protocol.error_table import DURING_ERROR, PROGRAM_NOT_FOUND
from melfa.robot import ControllerError, Robot, RobotError, Stopped
from melfa.robot.status import Alarm

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
        help="Serial device (/dev/ttyUSB0, COM3), tcp://host:port, a pyserial URL "
        "(socket://, rfc2217://) or 'sim': a throw-away simulator that lives only for this "
        "one command (start `melfa sim --tcp 127.0.0.1:7000` for one that keeps what you "
        f"upload). Default: ${ROBOT_ENV}, else sim.",
    ),
]
BaudOpt = Annotated[
    int, typer.Option("--baud", help="Baud rate; must match the controller's CBAU232.")
]
ParityOpt = Annotated[str, typer.Option("--parity", help="Parity N, E or O; must match CPRTY232.")]
StopbitsOpt = Annotated[
    int, typer.Option("--stopbits", help="Stop bits 1 or 2; must match CSTOP232.")
]
TimeoutOpt = Annotated[
    float,
    typer.Option("--timeout", metavar="S", help="Seconds to wait for each reply before giving up."),
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


_SHARED_OPTIONS: tuple[tuple[str, Any, Any], ...] = (
    ("robot", RobotOpt, None),
    ("baud", BaudOpt, 9600),
    ("parity", ParityOpt, "E"),
    ("stopbits", StopbitsOpt, 2),
    ("timeout", TimeoutOpt, DEFAULT_TIMEOUT_S),
    ("trace", TraceOpt, False),
)


def robot_command(
    *args: Any, **kwargs: Any
) -> Callable[[Callable[..., None]], Callable[..., None]]:
    """`app.command` for a command that talks to a robot.

    Adds the connection options every such command shares (--robot, --baud, --parity,
    --stopbits, --timeout, --trace, in one place) and hands the command the `Target` they
    describe as its keyword-only ``target`` argument.
    """

    def decorate(fn: Callable[..., None]) -> Callable[..., None]:
        own = [
            p
            for p in inspect.signature(fn, eval_str=True).parameters.values()
            if p.name != "target"
        ]
        shared = [
            inspect.Parameter(
                name, inspect.Parameter.KEYWORD_ONLY, default=default, annotation=hint
            )
            for name, hint, default in _SHARED_OPTIONS
        ]

        @functools.wraps(fn)
        def command(*a: Any, **kw: Any) -> None:
            options = [kw.pop(name) for name, _, _ in _SHARED_OPTIONS]
            fn(*a, target=_target(*options), **kw)

        params = [*own, *shared]
        command.__signature__ = inspect.Signature(params)  # type: ignore[attr-defined]
        command.__annotations__ = {p.name: p.annotation for p in params}
        app.command(*args, **kwargs)(command)
        return fn

    return decorate


RESET_HINT = "clear it with `melfa reset`"


def alarm_hint(alarm: Alarm | None) -> str:
    """The sentence that ends a refusal while an alarm is active.

    >>> alarm_hint(Alarm(2600, "L2600 Position data exceeds the limit"))
    'An alarm is active (L2600 Position data exceeds the limit): clear it with `melfa reset`.'
    """
    what = f" ({alarm.detail})" if alarm is not None else ""
    return f"An alarm is active{what}: {RESET_HINT}."


def _is_serial(spec: str) -> bool:
    return "://" not in spec and spec != SIM_SPEC and not spec.startswith(SIM_SPEC + ":")


def link_advice(spec: str, settings: LinkSettings) -> str:
    """What to check after a link failure, for the kind of port ``spec`` is.

    >>> print(link_advice("/dev/ttyUSB0", LinkSettings()))  # doctest: +ELLIPSIS
    Check the cable ... that --baud 9600 --parity E --stopbits 2 match the controller's ...
    """
    if _is_serial(spec) or spec.startswith(("rfc2217://", "spy://", "loop://")):
        return (
            "Check the cable and that the controller is switched on, and that --baud "
            f"{settings.baudrate} --parity {settings.parity} --stopbits {settings.stopbits} "
            "match the controller's CBAU232/CPRTY232/CSTOP232."
        )
    return (
        "Check the address and that the controller (or `melfa sim --tcp HOST:PORT`) is "
        "running there."
    )


SIM_HINT = (
    "--robot sim is a throw-away simulator, empty for every command: start "
    "`melfa sim --tcp 127.0.0.1:7000` and use --robot tcp://127.0.0.1:7000 to keep an upload."
)


def _refusal_message(exc: ControllerError, robot: Robot | None, target: Target) -> str:
    text = str(exc)
    if exc.number == PROGRAM_NOT_FOUND and target.spec == SIM_SPEC:
        return f"{text}\n{SIM_HINT}"
    if robot is None or not (exc.alarm or exc.number == DURING_ERROR):
        return text
    alarm: Alarm | None = None
    with contextlib.suppress(Exception):
        alarm = robot.active_alarm()
    if alarm is None and exc.number != DURING_ERROR:
        return text  # the alarm cleared itself meanwhile
    return f"{text}\n{alarm_hint(alarm)}"


def _link_failure(target: Target, message: str) -> typer.Exit:
    """Exit 3 with the port named and what to check (unless the message says already)."""
    if "plugged in" not in message:
        end = "" if message.endswith((".", "?", ")")) else "."
        message = f"{message}{end} {link_advice(target.spec, target.settings)}"
    return _fail(message, EXIT_LINK)


@contextlib.contextmanager
def _session(target: Target) -> Iterator[Robot]:
    """Open the robot and turn every failure into one message and its exit code."""
    robot: Robot | None = None
    try:
        robot = Robot.open(target.spec, target.settings, trace=target.trace)
        yield robot
    except ControllerError as exc:
        raise _fail(_refusal_message(exc, robot, target), EXIT_REFUSED) from None
    except Stopped as exc:
        raise _fail(str(exc), EXIT_REFUSED) from None
    except LinkTimeout as exc:
        raise _link_failure(target, f"no answer from {target.spec}: {exc}") from None
    except LinkError as exc:
        raise _link_failure(target, f"the link to {target.spec} failed: {exc}") from None
    except RemoteProtocolError as exc:
        raise _link_failure(target, f"garbled reply from {target.spec}: {exc}") from None
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


@robot_command(
    help="Check, number and upload a program (and its points) as program 1 in slot 1.\n\n"
    "Program and points go in one LOAD…SAVE session that replaces what was there; nothing "
    "is saved unless every line was accepted. The controller takes ASCII only: accents in "
    "comments and strings are sent as plain letters (your file is not changed). "
    "With --robot sim the upload goes to a throw-away simulator: start "
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
    *,
    target: Target,
) -> None:
    """See the help text above."""
    from melfa.cli.lang_commands import check_files, print_text
    from melfa.lang.diagnostics import Severity
    from melfa.lang.points import parse_points, upload_lines

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
    # The robot layer numbers an unnumbered program (jump targets rewritten) as it uploads.
    text, point_lines = _controller_ascii(program, text, points, point_lines)

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


def _controller_ascii(
    program: Path, text: str, points: Path | None, point_lines: list[str]
) -> tuple[str, list[str]]:
    """Accents in comments and strings go as plain letters (with one note); anything else
    non-ASCII (only possible with --force) is refused here, with where it is."""
    from melfa.robot.text import convert, find_non_ascii

    conversion = convert(text)
    note = conversion.note()
    if note is not None:
        _err.print(f"note: {escape(program.name)}: {escape(note)}")
    for path, lines in ((program, conversion.text), (points, point_lines)):
        bad = find_non_ascii(lines)
        if bad is not None and path is not None:
            where = f"{path}:{bad.line}:{bad.column}" if path == program else f"{path}"
            raise _fail(
                f"{where}: {bad.char!r} is not ASCII and is not in a comment or string; "
                "the controller only takes ASCII (rename it)",
                EXIT_REFUSED,
            )
    return conversion.text, point_lines


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


@robot_command()
def run(
    wait: Annotated[
        bool, typer.Option("--wait/--no-wait", help="Wait until the program has finished.")
    ] = False,
    *,
    target: Target,
) -> None:
    """Start program 1 in slot 1 once (cycle mode); needs a persistent robot, not sim.

    With --wait, exit 1 if the program stopped on an error (line and error shown)."""
    with _session(target) as session:
        session.run()
        if not wait:
            _out.print("started")
            return
        try:
            state = session.wait_idle(timeout=3600)
        except KeyboardInterrupt:
            session.stop()
            raise _fail("interrupted: robot stopped", EXIT_REFUSED) from None
        if state.status.error:
            status = session.status()
            line = f" at line {status.state.line}" if status.state.line else ""
            alarm = status.alarm or Alarm(state.status.error, "")
            raise _fail(
                f"the program stopped{line}: {alarm.detail}\n{alarm_hint(alarm)}", EXIT_REFUSED
            )
    _out.print("finished")


@robot_command()
def stop(
    *,
    target: Target,
) -> None:
    """Stop every slot and any motion now (needs no operation rights)."""
    with _session(target) as session:
        session.stop()
    _out.print("stopped")


@robot_command()
def delete(
    *,
    target: Target,
) -> None:
    """Delete program 1 and its points from the controller."""
    with _session(target) as session:
        session.delete()
    _out.print("deleted")


@robot_command("exec")
def exec_(
    statement: Annotated[str, typer.Argument(help='One statement, e.g. "MOV P1" or "OVRD 20".')],
    *,
    target: Target,
) -> None:
    """Execute one MELFA BASIC statement now; returns when accepted (the arm may still move)."""
    if not statement.strip():
        raise _fail("empty statement", EXIT_USAGE)
    with _session(target) as session:
        session.exec(statement)
    _out.print("accepted")


@robot_command()
def pose(
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    *,
    target: Target,
) -> None:
    """Show the tool pose (X Y Z mm, A B C deg, flags) and the joints J1–J6 (deg)."""
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


@robot_command()
def hand(
    action: Annotated[HandAction, typer.Argument(help="open or close.")],
    number: Annotated[int, typer.Argument(min=1, max=8, help="Hand number 1–8.")] = 1,
    *,
    target: Target,
) -> None:
    """Open or close a hand (EXECHOPEN n / EXECHCLOSE n)."""
    with _session(target) as session:
        session.hand(action is HandAction.OPEN, number)
    _out.print(f"hand {number} {action.value}")


class OnOff(enum.StrEnum):
    ON = "on"
    OFF = "off"


@robot_command()
def servo(
    state: Annotated[OnOff, typer.Argument(help="on or off.")],
    *,
    target: Target,
) -> None:
    """Switch the servo power on (needed before any move) or off."""
    with _session(target) as session:
        session.servo(state is OnOff.ON)
    _out.print(f"servo {state.value}")


@robot_command()
def reset(
    *,
    target: Target,
) -> None:
    """Clear the active alarm (RSTALRM), e.g. after a refused move; exit 1 if one remains."""
    with _session(target) as session:
        before = session.active_alarm()
        after = session.reset_alarm()
    if after is not None:
        raise _fail(
            f"the alarm is still active after the reset: {after.detail} (an emergency stop, "
            "or a fault that is still there, must be resolved at the robot first)",
            EXIT_REFUSED,
        )
    _out.print(f"cleared {before.detail}" if before is not None else "no alarm was active")


@robot_command()
def status(
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    *,
    target: Target,
) -> None:
    """Show whether a program runs (and which line), servo, override and any active alarm."""
    with _session(target) as session:
        report = session.status()
    if as_json:
        _out.print_json(json.dumps(report.to_json()))
        return
    state = report.state
    program = state.program or "none selected"
    line = f", line {state.line}" if state.line else ""
    override = f"{state.override} %" if state.override is not None else "unknown"
    _out.print(f"run       {report.run_state} (program {program}{line})")
    _out.print(f"servo     {'on' if report.servo_on else 'off'}")
    _out.print(f"override  {override}")
    if report.alarm is None:
        _out.print("alarm     none")
    else:
        _out.print(f"alarm     {escape(report.alarm.detail)} ({RESET_HINT})")


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


JOG_KEY_MAP = (
    "hold w/s: +X/-X   a/d: +Y/-Y   up/down arrows: +Z/-Z   (release to stop)\n"
    "space: open/close the hand   q: quit"
)


@robot_command(
    help="Jog from the keyboard: hold w/s (±X), a/d (±Y), up/down (±Z); space opens or "
    "closes the hand; q quits. The arm moves only while a key is held. Needs an interactive "
    "terminal (not a pipe or a script)."
)
def jog(
    override: Annotated[
        int, typer.Option("--override", min=1, max=100, help="Jog speed override, %.")
    ] = 10,
    hand_number: Annotated[int, typer.Option("--hand", min=1, max=8, help="Hand for space.")] = 1,
    *,
    target: Target,
) -> None:
    """See the help text above."""
    if not sys.stdin.isatty():
        raise _fail(
            "melfa jog reads held keys, so it needs an interactive terminal (stdin is not a "
            'TTY); run it in a terminal window, or script moves with `melfa exec "MVS '
            'P_CURR+(0,0,10,0,0,0)"`',
            EXIT_USAGE,
        )
    import termios
    import tty

    fd = sys.stdin.fileno()
    saved = termios.tcgetattr(fd)
    _out.print(JOG_KEY_MAP)
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
