"""Prepare an upload: the one place that turns program and points text into EMDAT items.

The CLI, the web API, the service, ROS and `Robot` all call `prepare_upload`, so a program
goes to the controller the same way from every entry:

- program: accents in comments and strings folded to ASCII (`melfa.robot.text`, line count
  unchanged); any other non-ASCII character refused with where it is; an unnumbered program
  numbered 10, 20, … with `melfa.lang.numbering.number_lines` (jump targets rewritten);
- points: read with `melfa.lang.points.parse_points` (``DEF POS``/``DEF JNT`` lines, or the
  controller's own ``P1=(…)(7,0)``), errors refused with their line, written back in the
  controller's form by `melfa.lang.points.upload_lines`.

>>> prepared = prepare_upload("MOV P1 ' repòs\\nEND\\n", "DEF POS P1=(1,2,3,4,5,6)(7,0)\\n")
>>> [item.text for item in prepared.items]
["10 MOV P1 ' repos", '20 END', 'P1=(1.00,2.00,3.00,4.00,5.00,6.00)(7,0)']
>>> prepared.program_lines, prepared.point_count, prepared.note
(2, 1, 'comments on line 1 sent without accents; your file is unchanged')
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from melfa.lang.numbering import NumberingError, number_lines
from melfa.lang.points import parse_points, upload_lines
from melfa.robot.errors import RobotError
from melfa.robot.text import convert, find_non_ascii

_NUMBERED = re.compile(r"\s*\d+(\s|$)")


@dataclass(frozen=True)
class UploadItem:
    """One EMDAT item and where it came from (1-based line of the caller's text)."""

    text: str
    source_line: int
    source: str = "program"


class UploadPreparationError(RobotError):
    """Program or points that cannot be sent as they are; ``source`` (program or points),
    ``line`` and ``column`` say where (1-based)."""

    def __init__(self, message: str, *, source: str, line: int, column: int = 1) -> None:
        super().__init__(f"{source} line {line}: {message}")
        self.source = source
        self.line = line
        self.column = column
        self.reason = message


@dataclass(frozen=True)
class PreparedUpload:
    """What goes to the controller, in order: program steps, then points."""

    items: tuple[UploadItem, ...]
    program_lines: int = 0
    point_count: int = 0
    note: str | None = None
    """What was changed on the way (accents folded), for the user; None if nothing."""
    has_program: bool = field(default=True)

    @property
    def program_texts(self) -> tuple[str, ...]:
        """The program's steps as sent."""
        return tuple(i.text for i in self.items if i.source == "program")

    @property
    def point_texts(self) -> tuple[str, ...]:
        """The points as sent (``P1=(…)(7,0)``)."""
        return tuple(i.text for i in self.items if i.source == "points")


def _text(value: str | Sequence[str]) -> str:
    return value if isinstance(value, str) else "\n".join(value)


def program_items(program: str | Sequence[str]) -> list[UploadItem]:
    """Program text -> numbered EMDAT items (see the module doc)."""
    return _program(program)[0]


def _program(program: str | Sequence[str]) -> tuple[list[UploadItem], str | None]:
    """Program text -> numbered EMDAT items and the note on what was folded to ASCII."""
    conversion = convert(_text(program))
    lines = [line.rstrip("\r\n \t") for line in conversion.text.splitlines()]
    bad = find_non_ascii(lines)
    if bad is not None:
        raise UploadPreparationError(
            f"{bad.char!r} is not ASCII and is not in a comment or string; the controller "
            "only takes ASCII (rename it)",
            source="program",
            line=bad.line,
            column=bad.column,
        )
    if not all(_NUMBERED.match(line) for line in lines if line.strip()):
        try:
            lines = number_lines("\n".join(lines)).split("\n")
        except NumberingError as exc:
            first = exc.diagnostics[0]
            raise UploadPreparationError(
                f"cannot number the program: {first.message}",
                source="program",
                line=first.line,
                column=first.column,
            ) from None
    items = [
        UploadItem(line.strip(), index, "program")
        for index, line in enumerate(lines, start=1)
        if line.strip()
    ]
    return items, conversion.note()


def point_items(points: str | Sequence[str]) -> list[UploadItem]:
    """Points text -> EMDAT items ``Pname=(…)(fl1,fl2)``; the first error is refused."""
    parsed = parse_points(_text(points))
    errors = [d for d in parsed.diagnostics if d.is_error]
    if errors:
        first = errors[0]
        raise UploadPreparationError(
            first.message, source="points", line=first.line, column=first.column
        )
    texts = upload_lines(parsed.points)
    return [
        UploadItem(text, point.line or index + 1, "points")
        for index, (point, text) in enumerate(zip(parsed.points, texts, strict=True))
    ]


def prepare_upload(
    program: str | Sequence[str] | None, points: str | Sequence[str] | None = None
) -> PreparedUpload:
    """Program and/or points -> the items to send; `UploadPreparationError` with where."""
    items: list[UploadItem] = []
    note = None
    program_count = 0
    if program is not None:
        steps, note = _program(program)
        items += steps
        program_count = len(steps)
    point_list = point_items(points) if points is not None else []
    items += point_list
    return PreparedUpload(
        tuple(items), program_count, len(point_list), note, has_program=program is not None
    )
