"""Typed readings of the answers to OPEN, JPOSF/PPOSF, STATE, DSTATE, HNDSTS and ERROR.

Each type parses the text after ``QoK``/``Qok`` (`parse`) and writes it back (`to_answer`),
so the virtual controller builds its answers with the same code the client reads them with.
Parsers are tolerant where real controllers vary (``****`` for a missing axis, extra L1/L2 or
J7/J8 axes, a trailing CR LF) and raise only `RemoteProtocolError` otherwise.

>>> p = Position.parse("X;522.13;Y;288.62;Z;215.49;A;178.59;B;-13.61;C;1.90;;7,0;100;0.00;00000000")
>>> p["X"], p.fl1, p.fl2, p.override
(522.13, 7, 0, 100)
>>> DState.parse("09060;17;1").status.run
<RunStatus.REPEAT|TEACH: 9>
"""

from __future__ import annotations

import enum
import math
import re
from dataclasses import dataclass, field

from melfa.protocol.error_table import ErrorLevel
from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.limits import HANDS

POSITION_UNKNOWN_TEXT = "position unknown (origin or encoder not set)"
"""How a ``****`` position reads to a person [TRACE K9b-C4]."""


class PositionUnknown(ValueError):
    """The controller shows ``****`` for an axis: it does not know the position (origin or
    encoder not set, or the axis is absent). A state of the robot, not a garbled reply."""

    def __init__(self, axis: str) -> None:
        super().__init__(f"{POSITION_UNKNOWN_TEXT}: axis {axis} shows ****")
        self.axis = axis


def _strip(answer: str) -> str:
    return answer.rstrip("\r\n")


def _int(text: str, what: str, base: int = 10) -> int:
    try:
        return int(text, base)
    except ValueError:
        raise RemoteProtocolError(f"{what}: {text[:20]!r} is not a number") from None


def _float(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise RemoteProtocolError(f"{what}: {text[:20]!r} is not a number") from None
    if not math.isfinite(value):
        raise RemoteProtocolError(f"{what}: {text[:20]!r} is not a finite number")
    return value


# ---------------------------------------------------------------------------------- OPEN


@dataclass(frozen=True)
class OpenBanner:
    """The answer to ``OPEN=<client>`` [DOC S1 §5.2.1; TRACE S10 CR2B/RV-3SB]::

        3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-3SB;CRn-5xx;MELFA;05-07-14;Ver.K4a;ENG;…;1;1;8;

    ``task_max`` is the last numeric field; the edit slot is ``task_max + 1``.
    """

    xyz_axes: int
    joint_axes: int
    program_extension: str
    robot_type: str
    controller: str
    date: str
    version: str
    language: str
    task_max: int | None
    fields: tuple[str, ...] = field(repr=False, default=())

    @property
    def edit_slot(self) -> int | None:
        """TASKMAX + 1 [DOC S1 §3.3.1]."""
        return None if self.task_max is None else self.task_max + 1

    @classmethod
    def parse(cls, answer: str) -> OpenBanner:
        """Read the banner; needs at least the first 12 fields."""
        fields = tuple(_strip(answer).split(";"))
        if len(fields) < 12:
            raise RemoteProtocolError(f"OPEN banner has {len(fields)} fields, expected ≥ 12")
        task_max = None
        for text in reversed(fields[12:]):
            if text:
                ascii_number = text.isascii() and text.isdigit() and len(text) < 4
                task_max = int(text) if ascii_number else None  # not int("²")
                break
        return cls(
            xyz_axes=_int(fields[0], "OPEN XYZ axes", 16),
            joint_axes=_int(fields[1], "OPEN joint axes", 16),
            program_extension=fields[4],
            robot_type=fields[6],
            controller=fields[7],
            date=fields[9],
            version=fields[10],
            language=fields[11],
            task_max=task_max,
            fields=fields,
        )

    def to_answer(self) -> str:
        """Banner text; uses ``fields`` when present, else a CR2B-like default layout."""
        if self.fields:
            return ";".join(self.fields)
        task = "" if self.task_max is None else str(self.task_max)
        return ";".join(
            [
                f"{self.xyz_axes:X}",
                f"{self.joint_axes:X}",
                "7,0",
                "3,5,A,1E,32,46,64",
                self.program_extension,
                "PRM",
                self.robot_type,
                self.controller,
                "MELFA",
                self.date,
                self.version,
                self.language,
                "COPYRIGHT",
                "1",
                "1",
                task,
                "",
            ]
        )


# ------------------------------------------------------------------------- JPOSF / PPOSF


@dataclass(frozen=True)
class Position:
    """A JPOSF/PPOSF/XPOSF/RPOSF answer [DOC S1 p.65]::

        <name>;<value>;…;;<FL1>,<FL2>;<override>;<end speed mm/s>;<limits 8 hex>

    Parsed as name/value pairs up to the first empty field, then the tail [DERIVED]. Axis
    values shown as ``****`` (axis absent) are None, as are ``****`` flags in joint answers.
    """

    axes: tuple[tuple[str, float | None], ...]
    fl1: int | None = None
    fl2: int | None = None
    override: int | None = None
    speed: float | None = None
    limits: int | None = None

    def __getitem__(self, name: str) -> float | None:
        for axis, value in self.axes:
            if axis == name:
                return value
        raise KeyError(name)

    @property
    def names(self) -> tuple[str, ...]:
        """Axis names in reply order."""
        return tuple(name for name, _ in self.axes)

    @property
    def unknown(self) -> bool:
        """Every axis shows ``****``: the controller does not know where the arm is (origin
        or encoders not set) [TRACE K9b-C4]. Not a garbled reply."""
        return all(value is None for _, value in self.axes)

    def values(self, *names: str) -> tuple[float, ...]:
        """The named axes as floats. `PositionUnknown` if a named axis shows ``****``
        (origin or encoder not set), `RemoteProtocolError` if it is absent."""
        out = []
        for name in names:
            try:
                value = self[name]
            except KeyError:
                raise RemoteProtocolError(f"position answer has no axis {name}") from None
            if value is None:
                raise PositionUnknown(name)
            out.append(value)
        return tuple(out)

    @classmethod
    def parse(cls, answer: str) -> Position:
        """Read a position answer."""
        fields = _strip(answer).split(";")
        axes: list[tuple[str, float | None]] = []
        index = 0
        while index < len(fields) and fields[index] != "":
            name = fields[index]
            if index + 1 >= len(fields):
                raise RemoteProtocolError(f"position answer: axis {name[:8]!r} has no value")
            text = fields[index + 1]
            if not re.fullmatch(r"[A-Z][A-Z0-9]{0,3}", name):
                raise RemoteProtocolError(f"position answer: {name[:20]!r} is not an axis name")
            value = None if set(text) == {"*"} else _float(text, f"axis {name}")
            axes.append((name, value))
            index += 2
        if not axes:
            raise RemoteProtocolError("position answer has no axes")
        tail = fields[index + 1 :]
        fl1 = fl2 = override = limits = None
        speed = None
        if tail and tail[0]:
            flags = tail[0].split(",")
            if len(flags) != 2:
                raise RemoteProtocolError(f"position flags {tail[0][:20]!r} are not FL1,FL2")
            if set(flags[0]) != {"*"}:
                fl1 = _int(flags[0], "FL1")
            if set(flags[1]) != {"*"}:
                fl2 = _int(flags[1], "FL2")
        if len(tail) > 1 and tail[1]:
            override = _int(tail[1], "override")
        if len(tail) > 2 and tail[2]:
            speed = _float(tail[2], "end speed")
        if len(tail) > 3 and tail[3]:
            limits = _int(tail[3], "limit bits", 16)
        return cls(tuple(axes), fl1, fl2, override, speed, limits)

    def to_answer(self) -> str:
        """Answer text with two decimals, as the controller prints it."""
        parts: list[str] = []
        for name, value in self.axes:
            parts += [name, "****" if value is None else f"{value:.2f}"]
        flags = "****,****" if self.fl1 is None or self.fl2 is None else f"{self.fl1},{self.fl2}"
        parts += [
            "",
            flags,
            "" if self.override is None else str(self.override),
            "" if self.speed is None else f"{self.speed:.2f}",
            "" if self.limits is None else f"{self.limits:08X}",
        ]
        return ";".join(parts)


JOINT_NAMES = ("J1", "J2", "J3", "J4", "J5", "J6")
POSE_NAMES = ("X", "Y", "Z", "A", "B", "C")


# --------------------------------------------------------------------- STATE / DSTATE


class RunStatus(enum.IntFlag):
    """Run-status byte [DOC S1 p.55]; a set bit means the second meaning in the manual."""

    REPEAT = 0x01  # cycle / repeat
    CYCLE_STOP_OFF = 0x02  # cycle-stop ON / OFF
    MLOCK = 0x04  # MLOCK OFF / ON
    TEACH = 0x08  # auto / teach
    TEACH_RUNNING = 0x10  # running in teach
    SERVO_ON = 0x20  # servo OFF / ON
    RUNNING = 0x40  # STOP / RUN
    OPERATION_ENABLED = 0x80  # operation disabled / enabled (CNTL)


class StopStatus(enum.IntFlag):
    """Stop-status byte [DOC S1 p.55]. 0x80 is not in the manual's table; real controllers
    set it with every TEACH reading on record (``09920``, ``39920``, ``08860``) [TRACE K9b]."""

    EMG = 0x01
    STOP = 0x02
    WAIT = 0x04
    STOP_SIGNAL = 0x08
    PROGRAM_SELECT = 0x10
    PSEUDO_INPUT = 0x40
    TEACH_PENDANT = 0x80  # [GUESS from TRACE] T/B enabled: seen only with the TEACH bit


class ModeKey(enum.Enum):
    """The controller's MODE key, as far as STATE shows it [DOC S5 §4; DOC S1 p.55].

    The run-status TEACH bit tells TEACH from AUTO; AUTO (Op.) and AUTO (Ext.) look the same
    in STATE, so the client reports AUTO and learns the rest from refusals (6020)."""

    TEACH = "TEACH"
    AUTO = "AUTO"


@dataclass(frozen=True)
class Status:
    """The concatenated ``<RUN><STOP><ERRNO>`` field: 2 hex, 2 hex, then decimal error.

    >>> s = Status.parse("A1124220")
    >>> s.run
    <RunStatus.REPEAT|SERVO_ON|OPERATION_ENABLED: 161>
    >>> s.stop, s.error
    (<StopStatus.STOP|PROGRAM_SELECT: 18>, 4220)
    """

    run: RunStatus
    stop: StopStatus
    error: int = 0

    @property
    def mode(self) -> ModeKey:
        """TEACH when the run-status TEACH bit is set, else AUTO."""
        return ModeKey.TEACH if RunStatus.TEACH in self.run else ModeKey.AUTO

    @classmethod
    def parse(cls, text: str) -> Status:
        """Read the field."""
        if len(text) < 5 or not re.fullmatch(r"[0-9A-Fa-f]{4}\d{1,4}", text):
            raise RemoteProtocolError(f"status field {text[:20]!r} is not <2 hex><2 hex><errno>")
        return cls(RunStatus(int(text[:2], 16)), StopStatus(int(text[2:4], 16)), int(text[4:]))

    def to_field(self) -> str:
        """Field text."""
        return f"{int(self.run):02X}{int(self.stop):02X}{self.error}"


@dataclass(frozen=True)
class DState:
    """``DSTATE`` answer: ``<RUN><STOP><ERRNO>;<step>;<mech no>`` [DOC S1]."""

    status: Status
    step: int | None = None
    mechanism: int | None = None

    @classmethod
    def parse(cls, answer: str) -> DState:
        """Read the answer."""
        fields = _strip(answer).split(";")
        step = _int(fields[1], "DSTATE step") if len(fields) > 1 and fields[1] else None
        mech = _int(fields[2], "DSTATE mechanism") if len(fields) > 2 and fields[2] else None
        return cls(Status.parse(fields[0]), step, mech)

    def to_answer(self) -> str:
        """Answer text."""
        step = "" if self.step is None else str(self.step)
        mech = "" if self.mechanism is None else str(self.mechanism)
        return f"{self.status.to_field()};{step};{mech}"


@dataclass(frozen=True)
class State:
    """``STATE`` answer [DOC S1]::

    <prog>;<line>;<override>;<edit sts>;<RUN><STOP><ERRNO>;<step>;<mech>;;;;;;;;;
    <task prog>;<REP/CYC>;<START/ALWAYS/ERROR>;<priority>;<mech no>
    """

    program: str
    line: int | None
    override: int | None
    edit_status: str
    status: Status
    step: int | None = None
    mechanism: int | None = None
    task_program: str = ""
    mode: str = ""
    start_condition: str = ""
    priority: int | None = None
    mechanism_number: int | None = None

    @classmethod
    def parse(cls, answer: str) -> State:
        """Read the answer; fields after the status are optional."""
        fields = _strip(answer).split(";")
        if len(fields) < 5:
            raise RemoteProtocolError(f"STATE answer has {len(fields)} fields, expected ≥ 5")

        def number(index: int, what: str) -> int | None:
            if index < len(fields) and fields[index]:
                return _int(fields[index], what)
            return None

        # The tail is read from the end: the manual's layout has one more empty field than
        # its own example (``…;1;1;;;;;;;;;REP;START;1;0``, 19 fields) [DOC S1].
        tail = fields[7:]
        has_tail = len(tail) >= 5
        return cls(
            program=fields[0],
            line=number(1, "STATE line"),
            override=number(2, "STATE override"),
            edit_status=fields[3],
            status=Status.parse(fields[4]),
            step=number(5, "STATE step"),
            mechanism=number(6, "STATE mechanism"),
            task_program=tail[-5] if has_tail else "",
            mode=tail[-4] if has_tail else "",
            start_condition=tail[-3] if has_tail else "",
            priority=number(len(fields) - 2, "STATE priority") if has_tail else None,
            mechanism_number=number(len(fields) - 1, "STATE mechanism number")
            if has_tail
            else None,
        )

    def to_answer(self) -> str:
        """Answer text."""

        def opt(value: int | None) -> str:
            return "" if value is None else str(value)

        return ";".join(
            [
                self.program,
                opt(self.line),
                opt(self.override),
                self.edit_status,
                self.status.to_field(),
                opt(self.step),
                opt(self.mechanism),
                *[""] * 7,
                self.task_program,
                self.mode,
                self.start_condition,
                opt(self.priority),
                opt(self.mechanism_number),
            ]
        )


# --------------------------------------------------------------------------------- HNDSTS


@dataclass(frozen=True)
class HandStatus:
    """``HNDSTS`` answer [DOC S1 §5.2.56]: for each of the 8 hands
    ``<output signal>;<1 open, 2 closed>;<0 single, 1 double solenoid>``
    (``900;2;1;902;1;1;…``: hand n on output signal 900 + 2(n-1)).

    ``hands`` holds True (open), False (closed) or None (the field is missing or neither).

    >>> HandStatus.parse("900;2;1;902;1;1").hands
    (False, True, None, None, None, None, None, None)
    >>> HandStatus((True,) + (False,) * 7).to_answer()[:20]
    '900;1;1;902;2;1;904;'
    """

    hands: tuple[bool | None, ...]

    @classmethod
    def parse(cls, answer: str) -> HandStatus:
        """Read the answer; a hand whose field is missing or unknown reads None."""
        fields = _strip(answer).split(";")
        states = {"1": True, "2": False}
        return cls(
            tuple(
                states.get(fields[3 * i + 1]) if 3 * i + 1 < len(fields) else None
                for i in range(len(HANDS))
            )
        )

    def to_answer(self) -> str:
        """Answer text (an unknown hand as closed, like a controller's unused output)."""
        parts: list[str] = []
        for i, hand in enumerate(self.hands[: len(HANDS)]):
            parts += [str(900 + 2 * i), "1" if hand else "2", "1"]
        return ";".join(parts)


# ---------------------------------------------------------------------------------- ERROR


@dataclass(frozen=True)
class ErrorStatus:
    """``ERROR`` answer: empty when no error, else ``<err no>;<level>`` (``Qok4140;2``)."""

    number: int
    level: ErrorLevel | None = None

    @classmethod
    def parse(cls, answer: str) -> ErrorStatus | None:
        """None when the controller has no error."""
        fields = _strip(answer).split(";")
        if fields == [""] or fields[0] == "0":
            return None
        number = _int(fields[0], "ERROR number")
        level = None
        if len(fields) > 1 and fields[1]:
            value = _int(fields[1], "ERROR level")
            if value not in (1, 2, 3):
                raise RemoteProtocolError(f"ERROR level {value} is not 1–3")
            level = ErrorLevel(value)
        return cls(number, level)

    def to_answer(self) -> str:
        """Answer text."""
        return f"{self.number}" if self.level is None else f"{self.number};{int(self.level)}"
