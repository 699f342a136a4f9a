"""``melfa doctor``: what the controller on the other end is, and which of our guesses hold.

Read-only by default: it sends only requests that change nothing (the command table's
SESSION/READ kinds) plus STOP, which stops nothing that is not already stopped and is how
the STOP form is found. Never a motion, servo, hand or program command. With
``probe_upload`` it also writes, reads back and deletes a scratch program under a name no
program uses, to check the EMDAT limits, ``;`` inside lines, and what PDIR counts.

Each item is ok / refused (with the controller's text) / unknown. The settings it could
settle go to the robot profile (`melfa.robot.profile`) that later commands and ``melfa
serve`` use.
"""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass, field

from melfa.link import LinkError
from melfa.protocol import (
    ErrorLogEntry,
    ModeKey,
    Ok,
    Parameter,
    ProgramEntry,
    RemoteProtocolError,
    Reply,
    Request,
    State,
    changes_nothing,
    error_text,
)
from melfa.protocol.answers import RunStatus
from melfa.robot.client import Robot
from melfa.robot.edit import find_program, read_back
from melfa.robot.errors import RobotError
from melfa.robot.settings import RobotSettings
from melfa.robot.upload import prepare_upload

SCRATCH_PROGRAM = "MDOCTOR"
"""Name of the scratch program ``--probe-upload`` writes and deletes."""
LINE_PARAMETERS = ("CBAU232", "CPRTY232", "CSTOP232", "CTERM232", "CPRC232")
"""Serial settings of the controller [DOC S5], read with ``PAR<name>`` when it answers."""


class Verdict(enum.Enum):
    OK = "ok"
    REFUSED = "refused"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class Finding:
    """One line of the report."""

    item: str
    verdict: Verdict
    detail: str
    blocks: bool = False
    """True when this keeps the robot from being used (TEACH mode, an active alarm)."""


@dataclass
class Report:
    """Everything doctor found; ``settings`` are the profile fields it settled."""

    findings: list[Finding] = field(default_factory=list)
    settings: dict[str, object] = field(default_factory=dict)
    controller: str = ""

    @property
    def blocked(self) -> bool:
        """Something keeps the robot from being used."""
        return any(f.blocks for f in self.findings)

    def add(self, item: str, verdict: Verdict, detail: str, *, blocks: bool = False) -> None:
        self.findings.append(Finding(item, verdict, detail, blocks))


class ReadOnlyViolation(RobotError):
    """Doctor was about to send something that changes the controller (a bug in doctor)."""


def _ask(robot: Robot, command: str, *, allow_write: bool = False) -> Reply:
    """Send ``command`` unless it could change anything (STOP aside)."""
    if not allow_write and not changes_nothing(command) and command != "STOP":
        raise ReadOnlyViolation(f"doctor must not send {command!r}")
    return robot._raw(command, rights=False)


def _refusal(reply: Reply) -> str:
    code = getattr(reply, "code", None)
    number = getattr(reply, "error", 0)
    wire = code.wire if code is not None else f"{number:04d}"
    return f"{error_text(number)} (sent as {wire})"


def diagnose(robot: Robot, *, probe_upload: bool = False) -> Report:
    """Run every probe; link failures propagate (the caller exits 3)."""
    report = Report()
    banner = robot.connect()
    report.controller = f"{banner.robot_type} {banner.controller} {banner.version}".strip()
    report.add("controller", Verdict.OK, f"{report.controller} ({banner.language})")
    if banner.edit_slot is not None:
        report.settings["edit_slot"] = banner.edit_slot
    _state(robot, report)
    _alarm_log(robot, report)
    _program(robot, report)
    _stop_form(robot, report)
    _handshakes(robot, report)
    _parameters(robot, report)
    report.add(
        "JOG over RS-232",
        Verdict.UNKNOWN,
        "cannot be probed without moving the arm; the client tries JOG and falls back to "
        "step moves (setting `jog`)",
    )
    if probe_upload:
        _probe_upload(robot, report)
    else:
        report.add(
            "EMDAT limits, ';' in lines, PDIR counts",
            Verdict.UNKNOWN,
            "not probed (read-only); run with --probe-upload",
        )
    return report


def _state(robot: Robot, report: Report) -> None:
    reply = _ask(robot, "STATE")
    if not isinstance(reply, Ok):
        report.add("state", Verdict.REFUSED, _refusal(reply))
        return
    state = State.parse(reply.answer)
    status = state.status
    mode = status.mode
    report.add(
        "mode key",
        Verdict.REFUSED if mode is ModeKey.TEACH else Verdict.OK,
        "TEACH: the teaching pendant holds the controller; turn the key to AUTO (Ext.)"
        if mode is ModeKey.TEACH
        else "AUTO (Op. or Ext.; a 6020 refusal later means Op.: turn it to AUTO (Ext.))",
        blocks=mode is ModeKey.TEACH,
    )
    servo = RunStatus.SERVO_ON in status.run
    report.add("servo", Verdict.OK, "on" if servo else "off")
    report.add("override", Verdict.OK, f"{state.override} %")
    if status.error:
        report.add("alarm", Verdict.REFUSED, error_text(status.error), blocks=True)
    else:
        report.add("alarm", Verdict.OK, "none active")


def _alarm_log(robot: Robot, report: Report) -> None:
    reply = _ask(robot, "ERRORRD<;0")
    if not isinstance(reply, Ok):
        report.add("error log", Verdict.REFUSED, _refusal(reply))
        return
    entry = ErrorLogEntry.parse(reply.answer)
    report.add(
        "error log",
        Verdict.OK,
        "empty"
        if entry is None
        else f"latest {entry.date} {entry.time}: {entry.number} {entry.text} ({entry.code.wire})",
    )


def _program(robot: Robot, report: Report) -> None:
    name = robot.settings.program
    try:
        entry = find_program(robot, name)
    except RobotError as exc:
        report.add(f"program {name}", Verdict.UNKNOWN, str(exc))
        return
    if entry is None:
        report.add(f"program {name}", Verdict.OK, "not on the controller (upload one)")
    else:
        report.add(
            f"program {name}",
            Verdict.OK,
            f"{entry.lines} steps, {entry.points} positions, {entry.size} bytes, {entry.stamp}",
        )


def _stop_form(robot: Robot, report: Report) -> None:
    for slot in (1, 0):
        reply = robot.channel.stop(Request("STOP", robot=robot.settings.robot, slot=slot))
        if isinstance(reply, Ok):
            report.add("STOP form", Verdict.OK, f"{robot.settings.robot};{slot};STOP accepted")
            report.settings["stop_slot"] = slot
            return
        report.add("STOP form", Verdict.REFUSED, f"{slot};STOP: {_refusal(reply)}")
    report.add("STOP form", Verdict.UNKNOWN, "neither form accepted: STOP cannot be relied on")


def _handshakes(robot: Robot, report: Report) -> None:
    accepted = True
    for command in ("PRTVERLISTL", "PRTVEREMDAT"):
        reply = _ask(robot, command)
        if not isinstance(reply, Ok):
            accepted = False
            report.add(command, Verdict.REFUSED, _refusal(reply))
    if accepted:
        report.add("PRTVER handshakes", Verdict.OK, "accepted")
    report.settings["prtver_handshakes"] = accepted


def _parameters(robot: Robot, report: Report) -> None:
    reply = _ask(robot, "PARRLNG")
    if isinstance(reply, Ok) and reply.answer.upper().startswith("RLNG;"):
        language = Parameter.parse(reply.answer)
        report.add(
            "RLNG (resynchronising request)",
            Verdict.OK,
            f"answered {reply.answer}; MELFA-BASIC IV = {language.values[0] == '1'}",
        )
    else:
        report.add(
            "RLNG (resynchronising request)",
            Verdict.REFUSED,
            "PARRLNG must be answered for the client to resynchronise after a timeout",
            blocks=True,
        )
    for name in LINE_PARAMETERS:
        reply = _ask(robot, f"PAR{name}")
        if isinstance(reply, Ok) and reply.answer:
            report.add(name, Verdict.OK, Parameter.parse(reply.answer).to_answer())
        else:
            report.add(name, Verdict.UNKNOWN, "not answered")


def _probe_upload(robot: Robot, report: Report) -> None:
    """Write, read back and delete a scratch program (the only writing doctor does)."""
    if find_program(robot, SCRATCH_PROGRAM) is not None:
        report.add("scratch upload", Verdict.UNKNOWN, f"{SCRATCH_PROGRAM} exists; not touched")
        return
    # Long comment lines (statements stop at 127 characters, L4210) so EMDAT requests are
    # packed to their limit, and a ';' inside a line.
    comments = "".join(f"{20 + 10 * i} ' {'x' * 110}\n" for i in range(5))
    program = f"10 ' doctor; a ';' inside a line\n{comments}80 END\n"
    points = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    prepared = prepare_upload(program, points)
    scratch = dataclasses.replace(
        robot.settings, program=SCRATCH_PROGRAM, slot_reset=False, confirm_counts=False
    )
    saved = robot.settings
    robot.settings = scratch
    try:
        report_upload = robot.load_project(prepared)
        held: ProgramEntry | None = report_upload.held
        counts = held is not None and (held.lines, held.points) == (7, 1)
        report.add(
            "PDIR counts",
            Verdict.OK if counts else Verdict.REFUSED,
            f"PDIR shows {held.lines if held else '?'} steps, {held.points if held else '?'} "
            "positions for 7 and 1 sent",
        )
        report.settings["confirm_counts"] = counts
        try:
            read_back(robot, prepared, clear=True)
            report.add("read-back (LISTL/LISTP), ';' in lines", Verdict.OK, "identical")
        except RobotError as exc:
            report.add("read-back (LISTL/LISTP), ';' in lines", Verdict.REFUSED, str(exc))
        report.add(
            "full EMDAT requests",
            Verdict.OK,
            f"{report_upload.requests} requests of up to 254 bytes accepted",
        )
    except RobotError as exc:
        report.add("scratch upload", Verdict.REFUSED, str(exc))
    except (LinkError, RemoteProtocolError):
        raise
    finally:
        try:
            robot._raw(f"FDEL{SCRATCH_PROGRAM}")
        finally:
            robot.settings = saved


def defaults_differ(report: Report) -> dict[str, object]:
    """The settings doctor found that differ from the defaults."""
    defaults = RobotSettings()
    return {k: v for k, v in report.settings.items() if getattr(defaults, k, None) != v}
