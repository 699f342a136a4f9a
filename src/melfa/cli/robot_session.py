"""What every robot command shares: the connection options (declared once), the `Target`
they describe, one session per command, and how failures become one message and an exit
code (0 done, 1 refused, 2 usage, 3 link failure or timeout, 4 saved but not confirmed)."""

from __future__ import annotations

import contextlib
import functools
import inspect
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, TextIO

import typer
from rich.console import Console
from rich.markup import escape

from melfa.cli.typer_app import app
from melfa.link import (
    DEFAULT_TIMEOUT_S,
    ROBOT_ENV,
    LinkBusy,
    LinkError,
    LinkSettings,
    LinkTimeout,
    RobotSpec,
    RobotSpecError,
    parse_robot,
)
from melfa.protocol import LocalProtocolError, PositionUnknown, RemoteProtocolError
from melfa.protocol.error_table import DURING_ERROR, PROGRAM_NOT_FOUND
from melfa.robot import (
    ControllerError,
    Robot,
    RobotError,
    SavedNotConfirmed,
    SaveOutcomeUnknown,
    Stopped,
    UploadPreparationError,
    VerifyFailed,
)
from melfa.robot.channel import RepliesOutOfStep
from melfa.robot.profile import profile_settings
from melfa.robot.status import Alarm

EXIT_REFUSED = 1
EXIT_USAGE = 2
EXIT_LINK = 3
EXIT_UNCONFIRMED = 4
"""Saved, but not confirmed: the controller holds the program; what it holds is unchecked."""

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
    Path | None,
    typer.Option(
        "--trace",
        metavar="FILE",
        help="Record every byte sent and received, with timestamps, to FILE ('-' for stderr; "
        "MELFA_TRACE=1 also prints to stderr). The file replays: attach it to a bug report.",
    ),
]


@dataclass(frozen=True)
class Target:
    """Where and how to connect, from the shared options."""

    robot: RobotSpec
    settings: LinkSettings
    trace: Path | None = None

    @property
    def spec(self) -> str:
        """The ``--robot`` text."""
        return self.robot.text


def robot_spec(value: str | None) -> RobotSpec:
    """``--robot`` checked by `melfa.link.parse_robot`; exit 2 with its message if bad."""
    try:
        return parse_robot(value)
    except RobotSpecError as exc:
        raise _fail(str(exc), EXIT_USAGE) from None


def _target(
    robot: str | None, baud: int, parity: str, stopbits: int, timeout: float, trace: Path | None
) -> Target:
    spec = robot_spec(robot)
    try:
        settings = LinkSettings(
            baudrate=baud, parity=parity.upper(), stopbits=stopbits, timeout=timeout
        )
    except ValueError as exc:
        raise _fail(str(exc), EXIT_USAGE) from None
    return Target(spec, settings, trace)


@contextlib.contextmanager
def trace_sink(path: Path | None) -> Iterator[Callable[[str], None] | None]:
    """Where ``--trace FILE`` lines go (None: no file; ``-``: stderr); exit 2 if unwritable."""
    if path is None:
        yield None
        return
    if str(path) == "-":
        yield lambda line: print(line, file=sys.stderr, flush=True)
        return
    try:
        handle: TextIO = path.open("a", encoding="utf-8")
    except OSError as exc:
        raise _fail(f"--trace {path}: cannot write it ({exc.strerror})", EXIT_USAGE) from None
    with handle:

        def write(line: str) -> None:
            handle.write(line + "\n")
            handle.flush()

        yield write


_SHARED_OPTIONS: tuple[tuple[str, Any, Any], ...] = (
    ("robot", RobotOpt, None),
    ("baud", BaudOpt, 9600),
    ("parity", ParityOpt, "E"),
    ("stopbits", StopbitsOpt, 2),
    ("timeout", TimeoutOpt, DEFAULT_TIMEOUT_S),
    ("trace", TraceOpt, None),
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


def link_advice(spec: str, settings: LinkSettings) -> str:
    """What to check after a link failure, for the kind of port ``spec`` is.

    >>> print(link_advice("/dev/ttyUSB0", LinkSettings()))  # doctest: +ELLIPSIS
    Check the cable ... that --baud 9600 --parity E --stopbits 2 match the controller's ...
    """
    if "://" not in spec or spec.startswith(("rfc2217://", "spy://", "loop://")):
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
    if exc.number == PROGRAM_NOT_FOUND and target.robot.is_sim:
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
    """Open the robot (with the profile `melfa doctor` wrote, and ``--trace``), and turn
    every failure into one message and its exit code."""
    robot: Robot | None = None
    with trace_sink(target.trace) as sink:
        try:
            robot = Robot.open(
                target.spec,
                target.settings,
                settings=profile_settings(target.spec),
                trace=True if sink is not None else None,
                trace_sink=sink,
            )
            yield robot
        except ControllerError as exc:
            raise _fail(_refusal_message(exc, robot, target), EXIT_REFUSED) from None
        except (Stopped, PositionUnknown, VerifyFailed, UploadPreparationError) as exc:
            raise _fail(str(exc), EXIT_REFUSED) from None
        except SavedNotConfirmed as exc:
            _err.print(f"[bold yellow]warning:[/] {escape(str(exc))}")
            raise typer.Exit(EXIT_UNCONFIRMED) from None
        except SaveOutcomeUnknown as exc:
            raise _fail(str(exc), EXIT_LINK) from None
        except LinkBusy as exc:
            raise _fail(str(exc), EXIT_LINK) from None
        except LinkTimeout as exc:
            raise _link_failure(target, f"no answer from {target.spec}: {exc}") from None
        except LinkError as exc:
            raise _link_failure(target, f"the link to {target.spec} failed: {exc}") from None
        except RepliesOutOfStep as exc:
            raise _link_failure(target, f"replies from {target.spec}: {exc}") from None
        except RemoteProtocolError as exc:
            raise _link_failure(target, f"garbled reply from {target.spec}: {exc}") from None
        except (LocalProtocolError, RobotError) as exc:
            raise _fail(str(exc), EXIT_USAGE) from None
        finally:
            if robot is not None:
                robot.close()
