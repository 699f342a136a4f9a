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

from melfa.lang.plan import plan_upload
from melfa.link import LinkError, LinkTimeout
from melfa.protocol import (
    OVERRIDE_PERCENT,
    ErrorLogEntry,
    LocalProtocolError,
    ModeKey,
    Ok,
    Parameter,
    Position,
    ProgramEntry,
    Refused,
    RemoteProtocolError,
    Reply,
    Request,
    State,
    changes_nothing,
    error_text,
)
from melfa.protocol.answers import RunStatus
from melfa.protocol.error_table import NO_RIGHTS, ORIGIN_NOT_SET
from melfa.protocol.messages import encode_reply
from melfa.robot.client import Robot
from melfa.robot.edit import find_program, read_back
from melfa.robot.errors import RobotError
from melfa.robot.settings import RobotSettings

SCRATCH_PROGRAM = "MDOCTOR"
"""Name of the scratch program ``--probe-upload`` writes and deletes."""
LINE_PARAMETERS = ("CBAU232", "CPRTY232", "CSTOP232", "CTERM232", "CPRC232")
"""Serial settings of the controller [DOC S5], read with ``PAR<name>`` when it answers."""
RAW_SHOWN = 120
"""A raw reply is quoted in the report up to this many characters."""


class Verdict(enum.Enum):
    OK = "ok"
    REFUSED = "refused"
    UNKNOWN = "unknown"


@dataclass(frozen=True)
class Finding:
    """One line of the report; ``raw`` is the reply exactly as it came (for a bug report)."""

    item: str
    verdict: Verdict
    detail: str
    blocks: bool = False
    """True when this keeps the robot from being used (TEACH mode, an active alarm)."""
    raw: str = ""


@dataclass
class Report:
    """Everything doctor found; ``settings`` are the profile fields it settled."""

    findings: list[Finding] = field(default_factory=list)
    settings: dict[str, object] = field(default_factory=dict)
    controller: str = ""
    link_failure: str | None = None
    """Why the probing ended early (the link failed or the session could not be opened)."""

    @property
    def blocked(self) -> bool:
        """Something keeps the robot from being used."""
        return any(f.blocks for f in self.findings)

    def add(
        self, item: str, verdict: Verdict, detail: str, *, blocks: bool = False, raw: str = ""
    ) -> None:
        self.findings.append(Finding(item, verdict, detail, blocks, raw))

    def render(self) -> list[str]:
        """The report as plain text lines (what the report file holds)."""
        width = max((len(f.item) for f in self.findings), default=0)
        lines = []
        for f in self.findings:
            mark = "  BLOCKS USE" if f.blocks else ""
            raw = f"  [reply: {f.raw}]" if f.raw else ""
            lines.append(f"{f.item:<{width}}  {f.verdict.value:<8}  {f.detail}{mark}{raw}")
        if self.link_failure:
            lines.append(f"probing ended early: {self.link_failure}")
        lines.append(f"verdict: {self.verdict}")
        return lines

    @property
    def verdict(self) -> str:
        """One sentence: usable, blocked, or the link failed."""
        if self.link_failure:
            return "the link failed: see above"
        if self.blocked:
            return "not usable yet: fix what BLOCKS USE"
        return "usable"


class ReadOnlyViolation(RobotError):
    """Doctor was about to send something that changes the controller (a bug in doctor)."""


class LinkLost(Exception):
    """The link failed under a probe (not a late or odd reply): probing cannot go on."""


@dataclass(frozen=True)
class Probe:
    """What one request got: ``reply`` (None when none came or it was unreadable) and
    ``raw``, the reply as received (or why there is none)."""

    command: str
    reply: Reply | None
    raw: str

    @property
    def ok(self) -> Ok | None:
        return self.reply if isinstance(self.reply, Ok) else None

    @property
    def refused(self) -> bool:
        return self.reply is not None and not isinstance(self.reply, Ok)


def _shown(text: str) -> str:
    return text if len(text) <= RAW_SHOWN else text[: RAW_SHOWN - 1] + "…"


def _raw_text(reply: Reply) -> str:
    return _shown(encode_reply(reply).decode("latin-1").rstrip("\r"))


def _probe(robot: Robot, command: str, *, allow_write: bool = False) -> Probe:
    """Send ``command`` (unless it could change anything) and take whatever reply comes in
    its turn, whatever its shape: a probe reports, it never dies on an answer."""
    if not allow_write and not changes_nothing(command) and command != "STOP":
        raise ReadOnlyViolation(f"doctor must not send {command!r}")
    request = Request(command, robot=robot.settings.robot, slot=robot.settings.slot)
    try:
        reply = robot.channel.request(request, check_fit=False)
    except LinkTimeout as exc:
        return Probe(command, None, _shown(f"no answer ({exc})"))
    except (RemoteProtocolError, LocalProtocolError) as exc:
        return Probe(command, None, _shown(f"unreadable ({exc})"))
    except LinkError as exc:
        raise LinkLost(f"{command}: {exc}") from None
    robot._note(reply)
    return Probe(command, reply, _raw_text(reply))


def _refusal(reply: Reply | None) -> str:
    code = getattr(reply, "code", None)
    number = getattr(reply, "error", 0)
    wire = code.wire if code is not None else f"{number:04d}"
    return f"{error_text(number)} (sent as {wire})"


def _unanswered(report: Report, item: str, probe: Probe, what: str) -> None:
    """A probe with no usable answer: refused (with the controller's text) or unknown."""
    if probe.refused:
        report.add(item, Verdict.REFUSED, _refusal(probe.reply), raw=probe.raw)
    else:
        report.add(item, Verdict.UNKNOWN, what, raw=probe.raw)


def diagnose(robot: Robot, *, probe_upload: bool = False) -> Report:
    """Run every probe; every answer, odd or not, becomes a line of the report. A link
    that fails (or an OPEN that cannot be read) ends the probing: `Report.link_failure`."""
    report = Report()
    try:
        banner = robot.connect()
    except (LinkError, RemoteProtocolError, RobotError) as exc:
        report.add("controller", Verdict.UNKNOWN, f"the session could not be opened: {exc}")
        report.link_failure = str(exc)
        return report
    report.controller = f"{banner.robot_type} {banner.controller} {banner.version}".strip()
    report.add("controller", Verdict.OK, f"{report.controller} ({banner.language})")
    if banner.edit_slot is not None:
        report.settings["edit_slot"] = banner.edit_slot
    try:
        state = _state(robot, report)
        _alarm_log(robot, report)
        _origin(robot, report, state)
        _program(robot, report)
        _rights(robot, report, state)
        _stop_form(robot, report)
        _handshakes(robot, report)
        _parameters(robot, report)
        report.add(
            "JOG over RS-232",
            Verdict.UNKNOWN,
            "cannot be probed without moving the arm; the client tries JOG and falls back "
            "to step moves (setting `jog`)",
        )
        if probe_upload:
            _probe_upload(robot, report)
        else:
            report.add(
                "EMDAT limits, ';' in lines, PDIR counts",
                Verdict.UNKNOWN,
                "not probed (read-only); run with --probe-upload",
            )
    except LinkLost as exc:
        report.link_failure = str(exc)
    return report


def _state(robot: Robot, report: Report) -> State | None:
    probe = _probe(robot, "STATE")
    unsafe = "the mode key and any alarm are unknown, so motion cannot be judged safe"
    if probe.ok is None:
        verdict = Verdict.REFUSED if probe.refused else Verdict.UNKNOWN
        report.add("state", verdict, f"no STATE answer: {unsafe}", blocks=True, raw=probe.raw)
        return None
    try:
        state = State.parse(probe.ok.answer)
    except RemoteProtocolError as exc:
        report.add(
            "state",
            Verdict.UNKNOWN,
            f"STATE answer not understood ({exc}): {unsafe}",
            blocks=True,
            raw=probe.raw,
        )
        return None
    status = state.status
    mode = status.mode
    report.add(
        "mode key",
        Verdict.REFUSED if mode is ModeKey.TEACH else Verdict.OK,
        "TEACH: the teaching pendant holds the controller; turn the key to AUTO (Ext.)"
        if mode is ModeKey.TEACH
        else "AUTO (Op. or Ext.: see 'operation rights')",
        blocks=mode is ModeKey.TEACH,
    )
    servo = RunStatus.SERVO_ON in status.run
    report.add("servo", Verdict.OK, "on" if servo else "off")
    report.add("override", Verdict.OK, f"{state.override} %")
    if status.error == ORIGIN_NOT_SET:
        report.add(
            "alarm",
            Verdict.REFUSED,
            f"{error_text(status.error)}: set the origin (encoder data) at the robot first",
            blocks=True,
            raw=probe.raw,
        )
    elif status.error:
        report.add("alarm", Verdict.REFUSED, error_text(status.error), blocks=True, raw=probe.raw)
    else:
        report.add("alarm", Verdict.OK, "none active")
    return state


def _alarm_log(robot: Robot, report: Report) -> None:
    probe = _probe(robot, "ERRORRD<;0")
    if probe.ok is None:
        _unanswered(report, "error log", probe, "no answer to ERRORRD")
        return
    try:
        entry = ErrorLogEntry.parse(probe.ok.answer)
    except RemoteProtocolError as exc:
        report.add(
            "error log",
            Verdict.UNKNOWN,
            f"answered, but not as the K9b firmware's 8-field entry ({exc})",
            raw=probe.raw,
        )
        return
    report.add(
        "error log",
        Verdict.OK,
        "empty"
        if entry is None
        else f"latest {entry.date} {entry.time}: {entry.number} {entry.text} ({entry.code.wire})",
    )


def _origin(robot: Robot, report: Report, state: State | None) -> None:
    """``JPOSF``: ``****`` axes mean the origin (encoder data) is lost [TRACE K9b-C4]."""
    probe = _probe(robot, "JPOSF")
    if probe.ok is None:
        what = "no JPOSF answer: whether the origin is set is unclear"
        _unanswered(report, "origin", probe, what)
        return
    try:
        position = Position.parse(probe.ok.answer)
    except RemoteProtocolError as exc:
        report.add("origin", Verdict.UNKNOWN, f"JPOSF answer not understood ({exc})", raw=probe.raw)
        return
    if any(value is None for _, value in position.axes):
        unknown = [name for name, value in position.axes if value is None]
        report.add(
            "origin",
            Verdict.REFUSED,
            f"lost: {', '.join(unknown)} show **** (origin or encoder data not set); nothing "
            "can move until it is set at the robot",
            blocks=True,
            raw=probe.raw,
        )
        return
    report.add("origin", Verdict.OK, "set (every joint has a position)")


def _program(robot: Robot, report: Report) -> None:
    name = robot.settings.program
    try:
        entry = find_program(robot, name)
    except LinkTimeout as exc:
        report.add(f"program {name}", Verdict.UNKNOWN, f"PDIR not answered ({exc})")
        return
    except (RobotError, RemoteProtocolError, LocalProtocolError) as exc:
        report.add(f"program {name}", Verdict.UNKNOWN, str(exc))
        return
    except LinkError as exc:
        raise LinkLost(f"PDIR: {exc}") from None
    if entry is None:
        report.add(f"program {name}", Verdict.OK, "not on the controller (upload one)")
    else:
        report.add(
            f"program {name}",
            Verdict.OK,
            f"{entry.lines} steps, {entry.points} positions, {entry.size} bytes, {entry.stamp}",
        )


def _rights(robot: Robot, report: Report, state: State | None) -> None:
    """Whether the computer gets the operation rights: ``CNTLON``, then ``OVRD=`` with the
    override STATE showed (it writes the value already there: changes nothing), then
    ``CNTLOFF``. A 6020 means the key is not at AUTO (Ext.): in AUTO (Op.) the operation
    panel holds the rights, which STATE cannot show [DOC S5 §4]."""
    item = "operation rights"
    if state is None or state.override is None or state.override not in OVERRIDE_PERCENT:
        report.add(item, Verdict.UNKNOWN, "not probed: the override is unknown")
        return
    taken = _probe(robot, "CNTLON")
    if taken.ok is None:
        _unanswered(report, item, taken, "no answer to CNTLON")
        return
    try:
        probe = _probe(robot, f"OVRD={state.override}", allow_write=True)
    finally:
        _probe(robot, "CNTLOFF")
    if probe.ok is not None:
        report.add(item, Verdict.OK, "granted (the key is at AUTO (Ext.))")
    elif isinstance(probe.reply, Refused) and probe.reply.error == NO_RIGHTS:
        report.add(
            item,
            Verdict.REFUSED,
            "refused (6020): the key is at AUTO (Op.) or TEACH; turn it to AUTO (Ext.)",
            blocks=True,
            raw=probe.raw,
        )
    else:
        _unanswered(report, item, probe, "no answer to OVRD=")


def _stop_form(robot: Robot, report: Report) -> None:
    for slot in (1, 0):
        command = f"{robot.settings.robot};{slot};STOP"
        try:
            reply = robot.channel.stop(Request("STOP", robot=robot.settings.robot, slot=slot))
        except LinkTimeout as exc:
            report.add("STOP form", Verdict.UNKNOWN, f"{command}: no answer ({exc})")
            continue
        except (RemoteProtocolError, LocalProtocolError) as exc:
            report.add("STOP form", Verdict.UNKNOWN, f"{command}: unreadable ({_shown(str(exc))})")
            continue
        except LinkError as exc:
            raise LinkLost(f"STOP: {exc}") from None
        if isinstance(reply, Ok):
            report.add("STOP form", Verdict.OK, f"{command} accepted", raw=_raw_text(reply))
            report.settings["stop_slot"] = slot
            return
        detail = f"{command}: {_refusal(reply)}"
        report.add("STOP form", Verdict.REFUSED, detail, raw=_raw_text(reply))
    report.add(
        "STOP",
        Verdict.REFUSED,
        "neither form accepted: STOP cannot be relied on; do not move the arm from melfa",
        blocks=True,
    )


def _handshakes(robot: Robot, report: Report) -> None:
    accepted = True
    for command in ("PRTVERLISTL", "PRTVEREMDAT"):
        probe = _probe(robot, command)
        if probe.ok is None:
            accepted = False
            _unanswered(report, command, probe, "no answer")
    if accepted:
        report.add("PRTVER handshakes", Verdict.OK, "accepted")
    report.settings["prtver_handshakes"] = accepted


def _parameters(robot: Robot, report: Report) -> None:
    item = "RLNG (resynchronising request)"
    probe = _probe(robot, "PARRLNG")
    answer = probe.ok.answer if probe.ok is not None else ""
    if answer.upper().startswith("RLNG;"):
        try:
            values = Parameter.parse(answer).values
            basic = f"; MELFA-BASIC IV = {values[0] == '1'}"
        except RemoteProtocolError:
            basic = ""
        report.add(item, Verdict.OK, f"answered {answer}{basic}", raw=probe.raw)
    else:
        report.add(
            item,
            Verdict.REFUSED if probe.refused else Verdict.UNKNOWN,
            "PARRLNG must be answered RLNG;… for the client to resynchronise after a timeout",
            blocks=True,
            raw=probe.raw,
        )
    for name in LINE_PARAMETERS:
        probe = _probe(robot, f"PAR{name}")
        answer = probe.ok.answer if probe.ok is not None else ""
        if probe.ok is None:
            _unanswered(report, name, probe, "not answered")
        elif answer.upper().startswith(name + ";"):
            try:
                report.add(name, Verdict.OK, Parameter.parse(answer).to_answer(), raw=probe.raw)
            except RemoteProtocolError as exc:
                report.add(name, Verdict.UNKNOWN, f"not understood ({exc})", raw=probe.raw)
        elif not answer:
            report.add(name, Verdict.UNKNOWN, "answered with no value", raw=probe.raw)
        else:
            report.add(name, Verdict.UNKNOWN, "answered without its name", raw=probe.raw)


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
    prepared = plan_upload(program, points)
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
            report.add("read-back (LISTL), ';' in lines", Verdict.OK, "identical")
        except RobotError as exc:
            report.add("read-back (LISTL), ';' in lines", Verdict.REFUSED, str(exc))
        _listp(robot, report)
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


def _listp(robot: Robot, report: Report) -> None:
    """Whether ``LISTPTOP`` reads the scratch program's position back (no real controller
    was recorded answering it): the profile's `listp_answered`, used by ``--verify``."""
    robot._call("NEW")
    robot._call(f"LOAD={SCRATCH_PROGRAM}")
    try:
        reply = robot._raw("LISTPTOP", slot=robot.edit_slot)
    finally:
        robot._call("NEW")
    answered = isinstance(reply, Ok) and reply.answer.upper().startswith("P1=")
    report.add(
        "LISTP (positions read back)",
        Verdict.OK if answered else Verdict.UNKNOWN,
        "answered: --verify reads positions back"
        if answered
        else "not answered: --verify counts positions with PDIR only",
        raw=_raw_text(reply),
    )
    report.settings["listp_answered"] = answered


def defaults_differ(report: Report) -> dict[str, object]:
    """The settings doctor found that differ from the defaults."""
    defaults = RobotSettings()
    return {k: v for k, v in report.settings.items() if getattr(defaults, k, None) != v}
