"""The controller's program memory and its edit slot.

A CR2-class controller keeps program steps and position data together in one program
(`<name>.MB4`) [melfa-basic-iv.md §12]. Programs are written through the edit slot:
`LOAD=<name>` opens a copy, `EMDAT`/`EDATA` change it, `SAVE` replaces the stored program,
`NEW` throws the copy away [DOC S1 §5.2.4–5.2.36]. This module is that memory and nothing
else: no protocol text, no clock (times are passed in).
"""

from __future__ import annotations

import datetime as dt
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from melfa.protocol.error_table import LINE_NUMBER_RANGE, STATEMENT_TOO_LONG, SYNTAX
from melfa.sim.config import MAX_LINE_NUMBER, MAX_STEP_CHARS

PROGRAM_EXT = "MB4"
"""[TRACE S10, S21] CRn-5xx programs are `.MB4`; a name without extension means .MB4 (rev N)."""

_NAME = re.compile(r"[A-Z0-9]{1,12}")
"""[melfa-basic-iv.md §1] Program names: letters and digits, at most 12 characters (L4120/L4130)."""


def program_name(raw: str) -> str | None:
    """Normalise a program name from a command argument (`1`, `test.mb4`) or None if invalid.

    >>> program_name("test.mb4"), program_name("COSIROP"), program_name("bad name")
    ('TEST', 'COSIROP', None)
    """
    name = raw.strip().upper()
    if name.endswith("." + PROGRAM_EXT):
        name = name[: -len(PROGRAM_EXT) - 1]
    return name if _NAME.fullmatch(name) else None


@dataclass(frozen=True, slots=True)
class Program:
    """A stored program: numbered steps (text as entered, number included) and positions
    (definition text `P1=(…)(7,0)` / `J1=(…)` keyed by upper-case name)."""

    name: str
    lines: Mapping[int, str] = field(default_factory=dict)
    positions: Mapping[str, str] = field(default_factory=dict)
    saved_at: dt.datetime = dt.datetime(2024, 1, 1)

    @property
    def file_name(self) -> str:
        return f"{self.name}.{PROGRAM_EXT}"

    def text(self) -> str:
        """The program as source text, steps in line-number order."""
        return "".join(self.lines[n] + "\n" for n in sorted(self.lines))

    def size(self) -> int:
        """Bytes the program takes, as PDIR shows it (text size; the real one is tokenised)."""
        return len(self.text()) + sum(len(p) + 1 for p in self.positions.values())


class EditError(Exception):
    """An EMDAT/EDATA item the controller refuses: error number and 1-based character position."""

    def __init__(self, number: int, column: int, message: str) -> None:
        super().__init__(message)
        self.number = number
        self.column = column


_LINE = re.compile(r"(\d+)(?:(\s+)(.*))?", re.DOTALL)
_POSITION = re.compile(r"([A-Za-z][A-Za-z0-9_]*)\s*=\s*\(")


@dataclass(frozen=True, slots=True)
class EditItem:
    """One EMDAT item after classification."""

    line: int | None = None  # a step number (with `text`) or a deletion (text None)
    text: str | None = None  # full step text, number included: "10 MOV P1"
    position: str | None = None  # upper-case name of a position definition
    definition: str | None = None  # "P1=(…)(7,0)"


def classify_item(raw: str) -> EditItem:
    """Read one EMDAT item: `10 MOV P1` (a step), `10` (delete step 10), `P1=(…)(7,0)`
    (a position). Raises `EditError` with the controller's number and the character.

    >>> classify_item("10 MOV P1")
    EditItem(line=10, text='10 MOV P1', position=None, definition=None)
    >>> classify_item(" 20")
    EditItem(line=20, text=None, position=None, definition=None)
    >>> classify_item("P1=(1,2,3,4,5,6)(7,0)").position
    'P1'
    """
    offset = len(raw) - len(raw.lstrip(" "))
    item = raw.strip(" ")
    match = _LINE.fullmatch(item)
    if match is not None:
        number = int(match.group(1))
        if not 1 <= number <= MAX_LINE_NUMBER:
            raise EditError(LINE_NUMBER_RANGE, offset + 1, f"line number {number} is not 1–32767")
        body = match.group(3)
        if body is None or not body.strip():
            return EditItem(line=number)
        text = f"{number} {body.rstrip()}"
        if len(text) > MAX_STEP_CHARS:
            raise EditError(
                STATEMENT_TOO_LONG, offset + MAX_STEP_CHARS + 1, f"step {number} is over 127 chars"
            )
        return EditItem(line=number, text=text)
    pos = _POSITION.match(item)
    if pos is not None and item.rstrip().endswith(")"):
        return EditItem(position=pos.group(1).upper(), definition=item.rstrip())
    raise EditError(SYNTAX, offset + 1, f"not a step, a step number or a position: {item!r}")


@dataclass
class EditBuffer:
    """The edit slot's working copy of one program."""

    name: str
    lines: dict[int, str] = field(default_factory=dict)
    positions: dict[str, str] = field(default_factory=dict)

    @classmethod
    def of(cls, name: str, program: Program | None) -> EditBuffer:
        if program is None:
            return cls(name)
        return cls(name, dict(program.lines), dict(program.positions))

    def apply(self, item: EditItem) -> None:
        if item.position is not None and item.definition is not None:
            self.positions[item.position] = item.definition
        elif item.line is not None and item.text is None:
            self.lines.pop(item.line, None)
        elif item.line is not None and item.text is not None:
            self.lines[item.line] = item.text

    def clear(self) -> None:
        self.lines.clear()
        self.positions.clear()

    def to_program(self, saved_at: dt.datetime) -> Program:
        return Program(self.name, dict(self.lines), dict(self.positions), saved_at)

    def text(self) -> str:
        return self.to_program(dt.datetime(2024, 1, 1)).text()


class ProgramStore:
    """Program memory: name -> `Program`, in creation order (as PDIR lists them [TRACE S21])."""

    def __init__(self, programs: Iterable[Program] = ()) -> None:
        self._programs: dict[str, Program] = {p.name: p for p in programs}

    def __contains__(self, name: object) -> bool:
        return name in self._programs

    def __len__(self) -> int:
        return len(self._programs)

    def get(self, name: str) -> Program | None:
        return self._programs.get(name)

    def names(self) -> list[str]:
        return list(self._programs)

    def put(self, program: Program) -> None:
        """Add or replace; a replaced program keeps its place in the directory."""
        self._programs[program.name] = program

    def delete(self, name: str) -> bool:
        return self._programs.pop(name, None) is not None

    def total_size(self) -> int:
        return sum(p.size() for p in self._programs.values())
