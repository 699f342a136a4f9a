"""Typed readings of the real controller's list answers: ERRORRD, PDIR, PAR/PNR.

Layouts read off real traffic [TRACE K9b, K4a-CR2B] (see ``tests/fixtures/real_traffic.py``);
each type parses the text after ``QoK``/``Qok`` and writes it back, so the virtual
controller answers with the same code the client reads.

>>> e = ErrorLogEntry.parse("22-08-24;11:28:22;5150;The origin has not been set;2;;0;515000100")
>>> e.number, e.text, e.level.letter, e.code.wire
(5150, 'The origin has not been set', 'L', '515000100')
>>> d = ProgramEntry.parse("TEST.MB4;964;23-02-0116:07:30;2;223488;12;;24;5;0;0;0;0")
>>> d.name, d.size, d.count, d.free, d.lines, d.points
('TEST', 964, 2, 223488, 24, 5)
>>> ProgramEntry.parse(";;;0;225536;;;;;;;").empty
True
>>> Parameter.parse("RLNG;1;1")
Parameter(name='RLNG', values=('1',), count=1)
"""

from __future__ import annotations

from dataclasses import dataclass

from melfa.protocol.error_table import ErrorCode, ErrorLevel
from melfa.protocol.errors import RemoteProtocolError


def _fields(answer: str, at_least: int, what: str) -> list[str]:
    fields = answer.rstrip("\r\n").split(";")
    if len(fields) < at_least:
        raise RemoteProtocolError(f"{what} answer has {len(fields)} fields, expected ≥ {at_least}")
    return fields


def _number(text: str, what: str) -> int:
    if not text.isascii() or not text.lstrip("-").isdigit():
        raise RemoteProtocolError(f"{what}: {text[:20]!r} is not a number")
    return int(text)


@dataclass(frozen=True)
class ErrorLogEntry:
    """One ``ERRORRD`` answer [TRACE K9b-C1/C3/C4]::

        <yy-mm-dd>;<hh:mm:ss>;<no>;<text>;<level>;<program>;<line>;<9-digit code>

    ``ERRORRD<;0`` (newest) and ``ERRORRD+1;0`` (next) answer an empty ``QoK``/``Qok`` when
    there is no (further) entry: `parse` returns None then.
    """

    date: str
    time: str
    number: int
    text: str
    level: ErrorLevel | None
    program: str
    line: int | None
    code: ErrorCode

    @classmethod
    def parse(cls, answer: str) -> ErrorLogEntry | None:
        """None for the empty answer."""
        if not answer.strip():
            return None
        f = _fields(answer, 8, "ERRORRD")
        number = _number(f[2], "ERRORRD number")
        level_value = _number(f[4], "ERRORRD level") if f[4] else None
        if level_value is not None and level_value not in (1, 2, 3):
            raise RemoteProtocolError(f"ERRORRD level {level_value} is not 1–3")
        try:
            code = ErrorCode.parse(f[7]) if f[7] else ErrorCode(number)
        except ValueError as exc:
            raise RemoteProtocolError(f"ERRORRD code: {exc}") from None
        return cls(
            date=f[0],
            time=f[1],
            number=number,
            text=f[3],
            level=None if level_value is None else ErrorLevel(level_value),
            program=f[5],
            line=_number(f[6], "ERRORRD line") if f[6] else None,
            code=code,
        )

    def to_answer(self) -> str:
        """Answer text."""
        level = "" if self.level is None else str(int(self.level))
        line = "" if self.line is None else str(self.line)
        fields = (self.date, self.time, str(self.number), self.text, level, self.program, line)
        return ";".join((*fields, self.code.wire))


@dataclass(frozen=True)
class ProgramEntry:
    """One ``PDIR`` answer [TRACE K9b-READ/PROG/DEL, K4a-CR2B]::

        PDIR< / PDIRTOP:  <name>.MB4;<bytes>;<date><time>;<count>;<free>;12;;<lines>;<points>;…
        PDIRnn:           <name>.MB4;<bytes>;<date><time>;12;;<lines>;<points>;…
        empty memory:     ;;;0;<free>;;;;;;;

    ``count`` and ``free`` (programs stored, free bytes) come only with the first entry.
    ``lines``/``points`` are the step and position counts [DERIVED: they match the
    uploads on record: 24 steps + 5 positions for the 964-byte REDUN]; the four numbers
    after them are unknown (checksums?) and kept in ``fields``.
    """

    name: str
    size: int | None
    stamp: str
    count: int | None
    free: int | None
    lines: int | None
    points: int | None
    fields: tuple[str, ...] = ()

    @property
    def empty(self) -> bool:
        """No program at this position (``;;;0;<free>…`` or an empty answer)."""
        return not self.name

    @classmethod
    def parse(cls, answer: str) -> ProgramEntry:
        """Read either layout (the first entry's has two more fields)."""
        if not answer.strip():
            return cls("", None, "", None, None, None, None, ())
        f = _fields(answer, 3, "PDIR")
        name = f[0].rsplit(".", 1)[0] if f[0] else ""
        # The PDIRnn layout has "12;;" at 3/4, the first-entry layout count;free at 3/4.
        first = len(f) > 4 and f[4] != ""
        rest = f[5:] if first else f[3:]

        def opt(index: int, what: str) -> int | None:
            return _number(rest[index], what) if len(rest) > index and rest[index] else None

        return cls(
            name=name,
            size=_number(f[1], "PDIR size") if f[1] else None,
            stamp=f[2],
            count=_number(f[3], "PDIR count") if first and f[3] else None,
            free=_number(f[4], "PDIR free") if first else None,
            lines=opt(2, "PDIR lines"),
            points=opt(3, "PDIR points"),
            fields=tuple(f),
        )


@dataclass(frozen=True)
class Parameter:
    """A ``PAR<name>`` / ``PNR<name>`` answer: ``<name>;<values>;<count>`` [TRACE K9b-C4,
    K4a-CR2B]. Values are split at ``,`` (``JOGJSP;0.10, 0.01, 10.00;3``)."""

    name: str
    values: tuple[str, ...]
    count: int | None

    @classmethod
    def parse(cls, answer: str) -> Parameter:
        """Read the answer; a value containing ``;`` (``RLNG;1;1``) keeps the last field as
        the count."""
        f = _fields(answer, 2, "parameter")
        count = _number(f[-1], "parameter count") if len(f) > 2 and f[-1] else None
        body = ";".join(f[1:-1]) if len(f) > 2 else f[1]
        values = tuple(v.strip() for v in body.split(","))
        return cls(f[0], values, count)

    def to_answer(self) -> str:
        """Answer text."""
        count = "" if self.count is None else str(self.count)
        return f"{self.name};{', '.join(self.values)};{count}"
