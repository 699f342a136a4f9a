"""`melfa upload|run|stop|override|delete|exec|pose|hand|servo|reset|status|jog`: drive a
controller.

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
3 link failure or timeout, 4 (upload) saved, but not confirmed, 130 Ctrl-C (`run --wait`
stops the robot first).
"""

from __future__ import annotations

import contextlib
import enum
import json
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich.markup import escape
from rich.progress import (
    BarColumn,
    DownloadColumn,
    Progress,
    TextColumn,
    TimeRemainingColumn,
)

from melfa.cli import EXIT_INTERRUPTED
from melfa.cli.robot_session import (
    EXIT_REFUSED,
    EXIT_USAGE,
    RESET_HINT,
    Target,
    _err,
    _fail,
    _out,
    _session,
    alarm_hint,
    robot_command,
)

if TYPE_CHECKING:
    from melfa.cli.checking import SourceFile
from melfa.protocol import (
    HANDS,
    JOINT_NAMES,
    OVERRIDE_PERCENT,
    POSE_NAMES,
    JogMode,
    span_text,
)
from melfa.protocol.answers import DState
from melfa.robot.status import Alarm

# --- upload ------------------------------------------------------------------------------


def _read_text(path: Path, what: str) -> tuple[str, SourceFile]:
    # Lazily (start-up): only the commands that send files need the file reader and checker.
    from melfa.cli.checking import FileKind, UsageError, read_text_file

    kind = FileKind.POINTS if what == "points" else FileKind.PROGRAM
    try:
        source = read_text_file(path, kind)
    except UsageError as exc:
        raise _fail(str(exc), EXIT_USAGE) from None
    return source.text, source


@robot_command(
    help="Check, number and upload a program (and its points) as program 1 in slot 1.\n\n"
    "Program and points go in one LOAD…SAVE session that replaces what was there; nothing "
    "is saved unless every line was accepted, and afterwards the controller's directory "
    "must list the program with as many steps and positions as were sent (--verify also "
    "reads every line back). The controller takes ASCII only: accents in comments and "
    "strings are sent as plain letters (your file is not changed). With --robot sim the "
    "upload goes to a throw-away simulator: start `melfa sim --tcp 127.0.0.1:7000` (or "
    "--pty) for one that persists between commands."
)
def upload(
    program: Annotated[Path, typer.Argument(help="MELFA BASIC IV program (.MB4).")],
    points: Annotated[
        Path | None, typer.Option("--points", "-p", help="Points file (.POS) to send too.")
    ] = None,
    force: Annotated[
        bool, typer.Option("--force", help="Upload even if the checker finds errors.")
    ] = False,
    verify: Annotated[
        bool,
        typer.Option("--verify", help="Read every line and position back after saving."),
    ] = False,
    *,
    target: Target,
) -> None:
    """See the help text above."""
    # Lazily (start-up): the other robot commands need neither the checker nor the uploader.
    from melfa.cli.checking import FileReport
    from melfa.cli.lang_commands import print_text
    from melfa.lang.diagnostics import Severity
    from melfa.lang.plan import plan_upload
    from melfa.lang.project import by_position
    from melfa.robot.upload import UploadPreparationError, sendable

    text, program_source = _read_text(program, "program")
    files = [(program, program_source)]
    points_text: str | None = None
    if points is not None:
        points_text, points_source = _read_text(points, "points")
        files.append((points, points_source))
    # One plan: the checker's findings, the lines to send and the step numbers.
    plan = plan_upload(text, points_text if points_text is not None else "")
    found = (plan.diagnostics, plan.point_diagnostics)
    reports = [
        FileReport(path, source, list(by_position([*source.diagnostics, *diagnostics])))
        for (path, source), diagnostics in zip(files, found, strict=False)
    ]
    errors = [d for r in reports for d in r.diagnostics if d.severity is Severity.ERROR]
    if errors and not force:
        print_text(reports, _err)
        raise _fail(
            f"{program}: not uploaded because of the errors above (--force to upload anyway)",
            EXIT_REFUSED,
        )
    try:
        prepared = sendable(plan)
    except UploadPreparationError as exc:
        path = program if exc.source == "program" else points
        raise _fail(f"{path}:{exc.line}:{exc.column}: {exc.reason}", EXIT_REFUSED) from None
    if prepared.note is not None:
        _err.print(f"note: {escape(program.name)}: {escape(prepared.note)}")

    with _session(target) as session, _progress() as bar:
        task = bar.add_task(f"upload {program.name}", total=None)

        def progress(sent: int, total: int) -> None:
            bar.update(task, completed=sent, total=total)

        report = session.load_project(prepared, progress=progress, verify=verify)
    _out.print(
        f"uploaded {program.name}"
        + (f" and {prepared.point_count} points" if points is not None else "")
        + f" to {target.spec}: {report.items} items in {report.requests} EMDAT requests, "
        f"{report.bytes_sent} bytes, {report.seconds:.1f} s; {report.confirmation}"
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


@robot_command()
def run(
    wait: Annotated[
        bool, typer.Option("--wait/--no-wait", help="Wait until the program has finished.")
    ] = False,
    resume: Annotated[
        bool,
        typer.Option("--resume", help="Continue a program paused by STOP where it stopped."),
    ] = False,
    *,
    target: Target,
) -> None:
    """Start program 1 in slot 1 once (cycle mode) from its first line; needs a persistent
    robot, not sim.

    With --wait, exit 1 if the program stopped on an error (line and error shown)."""
    with _session(target) as session:
        session.run(resume=resume)
        if not wait:
            _out.print("started")
            return
        started = time.monotonic()
        try:
            # On a terminal, the line it runs and for how long (stderr; nothing in a pipe).
            with _err.status("running…") as shown:

                def progress(now: DState) -> None:
                    where = f"line {now.step}" if now.step else "running"
                    shown.update(f"running {where}  ({time.monotonic() - started:.0f} s)")

                state = session.wait_idle(timeout=3600, on_state=progress)
        except KeyboardInterrupt:
            session.stop()
            _err.print("interrupted: robot stopped")
            raise typer.Exit(EXIT_INTERRUPTED) from None
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
    """Stop the program and any motion now (needs no operation rights)."""
    with _session(target) as session:
        session.stop()
    _out.print("stopped")


@robot_command()
def override(
    percent: Annotated[
        int,
        typer.Argument(
            min=OVERRIDE_PERCENT.start,
            max=OVERRIDE_PERCENT[-1],
            help=f"Override in per cent, {span_text(OVERRIDE_PERCENT)}.",
        ),
    ],
    *,
    target: Target,
) -> None:
    """Set the operation-panel override (OVRD=): it scales every speed, the program's own
    OVRD included. `melfa exec "OVRD 10"` sets the program's override instead, which the
    program's next OVRD statement replaces."""
    with _session(target) as session:
        value = session.override(percent)
    _out.print(f"override {value} %")


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
    number: Annotated[
        int, typer.Argument(min=HANDS.start, max=HANDS[-1], help=f"Hand number {span_text(HANDS)}.")
    ] = 1,
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
        int,
        typer.Option(
            "--override",
            min=OVERRIDE_PERCENT.start,
            max=OVERRIDE_PERCENT[-1],
            help="Jog speed override, %.",
        ),
    ] = 10,
    hand_number: Annotated[
        int, typer.Option("--hand", min=HANDS.start, max=HANDS[-1], help="Hand for space.")
    ] = 1,
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
