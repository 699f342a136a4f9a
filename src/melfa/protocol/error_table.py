"""Controller error numbers: the one home of their names, levels and texts.

Everything that knows an error number (client, virtual controller, service, CLI, the
student-facing texts built on top) reads it here. Texts are the controller's own where real
traffic recorded them (``ERRORMES`` answers and ``ERRORRD`` entries in
``tests/fixtures/real_traffic.py`` [TRACE]), else BFP-A5993-M (S4) as quoted in protocol.md
§2.3 and melfa-basic-iv.md §8 [DOC]. Replies carry the number without its letter
(``QeR6020`` is L6020), in the manual's 4-digit form or the real controller's 9-digit form
(`ErrorCode`: 4-digit number + 5 detail digits, ``602000000``).

>>> ERROR_MESSAGES[6020]
ErrorInfo(level=<ErrorLevel.LOW: 2>, message='The Operation is disable')
>>> error_text(6020), error_code(2000), error_code(9100, ErrorLevel.HIGH)
('L6020 The Operation is disable', 'L2000', 'H9100')
>>> ErrorCode.parse("515000100")
ErrorCode(number=5150, detail='00100')
>>> ErrorCode.parse("6020").wire, ErrorCode(6020, "00000").wire
('6020', '602000000')
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Final, NamedTuple


class ErrorLevel(enum.IntEnum):
    """An error's level: the ``ERROR`` answer's level field (1–3) [DOC S1], and the letter
    the manual writes before the number (``L2000``)."""

    HIGH = 1  # H: servo off
    LOW = 2  # L: operation stops
    CAUTION = 3  # C: operation continues

    @property
    def letter(self) -> str:
        """H, L or C, as in the troubleshooting manual's numbers."""
        return "HLC"[self.value - 1]

    @classmethod
    def from_letter(cls, letter: str) -> ErrorLevel:
        """``"H"``, ``"L"`` or ``"C"``; `ValueError` for anything else."""
        if len(letter) != 1 or letter not in "HLC":
            raise ValueError(f"{letter[:5]!r} is not an error level (H, L or C)")
        return cls("HLC".index(letter) + 1)


# ------------------------------------------------------------------- named numbers
# The numbers code branches on. [DOC S4] unless marked; [TRACE] = seen from a real controller.

ILLEGAL_COMMAND: Final = 6010
"""L6010: before OPEN, or unknown to this firmware [DOC S4]."""
NO_RIGHTS: Final = 6020
"""L6020 "The Operation is disable": no operation rights, or the mode key forbids it (a
real CRn-5xx answers SLOTINIT in TEACH with it although CNTLON was accepted) [TRACE K9b-PROG]."""
COMMAND_TOO_LONG: Final = 6080
"""C6080 "Com mesg is too long" [DOC S4]."""
COMMAND_SIZE_EXCEEDED: Final = 3270
"""L3270 the command size is exceeded [DOC S4]."""
BUSY: Final = 5640
"""L5640 "Cannot execute during RUN": the arm still moves [DOC S4; CODE S6/S7]."""
DURING_ERROR: Final = 5600
"""L5600 "Cannot execute during an error": only RSTALRM helps [DOC S4]."""
TB_ENABLED: Final = 5000
"""H5000 "TB Enable key is ON": the teaching pendant holds the controller [TRACE K9b-C4]."""
NOT_PSA: Final = 5120
"""5120 "Cannot select program (not PSA)": RUN refused, program selection not enabled
[TRACE K9b-RAW]."""
ORIGIN_NOT_SET: Final = 5150
"""L5150 "The origin has not been set" [TRACE K9b-C1]."""
SERVO_ON_DURING_ERROR: Final = 1630
"""C1630 cannot servo ON during an error [DOC S4]."""
SERVO_OFF: Final = 2000
"""L2000 "The servo is OFF" [DOC S4]."""
JOG_REFUSED: Final = 2030
"""L2030 "JOG operation cannot be accepted" [DOC S4]."""
JOINT_LIMIT: Final = 2160
"""H2160 "Joint angle exceeds the limit" [DOC S4]."""
XYZ_LIMIT: Final = 2180
"""H2180–H2193 "X/Y/Z data exceeds the limit" [DOC S4]."""
POSITION_LIMIT: Final = 2600
"""L2600–L2603 "Position data exceeds the limit" [DOC S4]."""
ILLEGAL_POSITION_DATA: Final = 2800
"""L2800–L2803 "Illegal position data" [DOC S4]."""
ARGUMENT_OUT_OF_RANGE: Final = 3110
"""[GUESS] an argument outside its range (OVRD=0, HNDON9, hand 9, SQR(-1)…): no public list
names the error."""
NUMERIC_OVERFLOW: Final = 3120
"""[GUESS] DEF INTE overflow (outside -32768..32767) and real overflow."""
GOSUB_NESTING_OVER: Final = 3220
"""[GUESS] GOSUB nested deeper than the controller allows (about 800 [S2c])."""
FOR_NEXT_UNMATCH: Final = 3230
"""L3230 FOR/NEXT unmatch [melfa-basic-iv.md §8]."""
NESTING_OVER: Final = 3240
"""L3240 FOR/WHILE nesting exceeds 16 [melfa-basic-iv.md §8]."""
WHILE_WEND_UNMATCH: Final = 3250
"""L3250 WHILE/WEND unmatch [melfa-basic-iv.md §8]."""
IF_ENDIF_UNMATCH: Final = 3252
"""L3252 IF/ENDIF unmatch [melfa-basic-iv.md §8]."""
SELECT_UNMATCH: Final = 3254
"""L3254 SELECT/END SELECT unmatch [melfa-basic-iv.md §8]."""
IF_ELSE_UNMATCH: Final = 3255
"""L3255 IF/ELSE unmatch [melfa-basic-iv.md §8]."""
DIVISION_BY_ZERO: Final = 3500
"""[GUESS] division by zero ([S2 p.164] says it is an error but not which number)."""
JUMP_DESTINATION_MISSING: Final = 3600
"""L3600 "Jump destination does not exist" [melfa-basic-iv.md §8]."""
UNDEFINED_VARIABLE: Final = 3700
"""L3700 a variable read before it was given a value [melfa-basic-iv.md §8]."""
RETURN_WITHOUT_GOSUB: Final = 3840
"""L3840 RETURN without GOSUB [melfa-basic-iv.md §8]."""
UNDEFINED_PALLET: Final = 3850
"""L3850 undefined PLT [melfa-basic-iv.md §8]."""
ILLEGAL_POSITION: Final = 3860
"""L3860 illegal position data [melfa-basic-iv.md §8]."""
BAD_PROGRAM_NAME: Final = 4120
"""L4120 illegal program name [melfa-basic-iv.md §8]."""
PROGRAM_NOT_FOUND: Final = 4140
"""L4140 "The program was not found" [DOC S4]."""
PROGRAM_BEING_EDITED: Final = 4170
"""L4170 "The program is being edited" [DOC S4]."""
PROGRAM_RUNNING: Final = 4180
"""L4180 "Program is running": a paused or running program holds the slot [DOC S4]."""
STATEMENT_TOO_LONG: Final = 4210
"""L4210 "Too long statement": a step over 127 characters [melfa-basic-iv.md §1, §8]."""
SYNTAX: Final = 4220
"""L4220 "Syntax error" [DOC S4]."""
LINE_NOT_FOUND: Final = 4230
"""L4230 "The line No. does not exist" [DOC S4]."""
VARIABLE_NAME_TOO_LONG: Final = 4300
"""L4300 variable name too long [DOC S4; TRACE K9b-C3]."""
VARIABLE_NOT_DEFINED: Final = 4340
"""L4340 "The variable is not defined" [DOC S4]."""
DUPLICATE_DEFINITION: Final = 4350
"""L4350 redefinition with DIM/DEF [melfa-basic-iv.md §8]."""
ARRAY_ELEMENT: Final = 4370
"""L4370 array element error (subscript out of range) [melfa-basic-iv.md §8]."""
TYPE_COMBINATION: Final = 4390
"""L4390 variable type combination [melfa-basic-iv.md §8]."""
LINE_NUMBER_RANGE: Final = 4420
"""L4420 "Line No exceeds 32767" [melfa-basic-iv.md §1, §8]."""

JOG_NOT_ACCEPTED: Final = frozenset({JOG_REFUSED, ILLEGAL_COMMAND})
"""Refusals of JOG meaning "this firmware does not take JOG here": fall back to steps."""


@dataclass(frozen=True)
class ErrorCode:
    """An error number as the controller wrote it: 4 digits (manual), or 4 + 5 detail
    digits (real CRn-5xx: ``602000000``, ERRORRD's ``515000100``) [TRACE K9b]."""

    number: int
    detail: str | None = None

    @classmethod
    def parse(cls, text: str) -> ErrorCode:
        """``"6020"`` or ``"602000000"``; `ValueError` for anything else."""
        if not text.isascii() or not text.isdigit() or len(text) not in (1, 2, 3, 4, 9):
            raise ValueError(f"{text[:20]!r} is not a 4- or 9-digit error number")
        if len(text) == 9:
            return cls(int(text[:4]), text[4:])
        return cls(int(text))

    @property
    def wire(self) -> str:
        """The digits as sent, for ``ERRORMES``: ``6020`` or ``602000000``."""
        return f"{self.number:04d}{self.detail or ''}"


class ErrorInfo(NamedTuple):
    """Level (H high: servo off, L low: operation stops, C caution) and message."""

    level: ErrorLevel
    message: str


_H, _L, _C = ErrorLevel.HIGH, ErrorLevel.LOW, ErrorLevel.CAUTION

_TABLE: dict[int, ErrorInfo] = {
    # protocol.md §2.3
    6010: ErrorInfo(_L, "Illegal command"),
    6020: ErrorInfo(_L, "The Operation is disable"),
    5640: ErrorInfo(_L, "Cannot execute during RUN"),
    5600: ErrorInfo(_L, "Cannot execute during an error"),
    5010: ErrorInfo(_L, "AUTOENA signal is OFF"),
    1630: ErrorInfo(_C, "Cannot servo ON during an error"),
    1640: ErrorInfo(_C, "Cannot servo ON: DEADMAN OFF"),
    2000: ErrorInfo(_L, "The servo is OFF"),
    2030: ErrorInfo(_L, "JOG operation cannot be accepted"),
    2160: ErrorInfo(_H, "Joint angle exceeds the limit"),
    **{n: ErrorInfo(_H, "X/Y/Z data exceeds the limit") for n in range(2180, 2194)},
    **{n: ErrorInfo(_L, "Position data exceeds the limit") for n in range(2600, 2604)},
    **{n: ErrorInfo(_L, "Illegal position data") for n in range(2800, 2804)},
    3270: ErrorInfo(_L, "The command size is exceeded (256 single-byte characters)"),
    4140: ErrorInfo(_L, "The program was not found"),
    4170: ErrorInfo(_L, "The program is being edited"),
    4180: ErrorInfo(_L, "Program is running"),
    4220: ErrorInfo(_L, "Syntax error"),
    4230: ErrorInfo(_L, "The line No. does not exist"),
    # The controller's own texts, from real ERRORMES answers / ERRORRD entries [TRACE K9b].
    4300: ErrorInfo(_L, "Too longvariable name"),
    5000: ErrorInfo(_H, "TB Enable key is ON"),
    5120: ErrorInfo(_L, "Cannot select program (not PSA)"),
    5150: ErrorInfo(_L, "The origin has not been set"),
    4340: ErrorInfo(_L, "The variable is not defined"),
    6080: ErrorInfo(_C, "Com mesg is too long"),
    # melfa-basic-iv.md §8
    3220: ErrorInfo(_L, "Nesting over (IF/FOR)"),
    3230: ErrorInfo(_L, "FOR/NEXT unmatch"),
    3240: ErrorInfo(_L, "FOR/WHILE nesting exceeds 16"),
    3250: ErrorInfo(_L, "WHILE/WEND unmatch"),
    3251: ErrorInfo(_L, "More than 32 jump destinations (ON GOTO)"),
    3252: ErrorInfo(_L, "IF/ENDIF unmatch"),
    3253: ErrorInfo(_L, "IF nesting exceeds 8"),
    3254: ErrorInfo(_L, "SELECT/END SELECT unmatch"),
    3255: ErrorInfo(_L, "IF/ELSE unmatch"),
    3600: ErrorInfo(_L, "Jump destination missing"),
    3700: ErrorInfo(_L, "Undefined (uninitialised) variable"),
    3840: ErrorInfo(_L, "RETURN without GOSUB"),
    3850: ErrorInfo(_L, "Undefined PLT"),
    3860: ErrorInfo(_L, "Illegal position data"),
    4120: ErrorInfo(_L, "Illegal program name"),
    4130: ErrorInfo(_L, "Illegal program name"),
    4210: ErrorInfo(_L, "Statement longer than 127 characters"),
    4310: ErrorInfo(_L, "Illegal character"),
    4350: ErrorInfo(_L, "Duplicate definition"),
    4370: ErrorInfo(_L, "Array element error"),
    4390: ErrorInfo(_L, "Variable type combination"),
    4420: ErrorInfo(_L, "Line No. exceeds 32767"),
    4440: ErrorInfo(_L, "Duplicate label"),
    4910: ErrorInfo(_L, "RLNG mismatch (1 = MELFA-BASIC IV, 0 = MOVEMASTER)"),
}

ERROR_MESSAGES: Mapping[int, ErrorInfo] = MappingProxyType(_TABLE)
"""Error number -> (level letter, message). Read-only."""


USER_ERRORS: Final = range(9000, 9300)
"""The numbers a program's own ``ERROR`` statement raises [DOC S1 ERROR]."""
USER_ERROR_LEVELS: Final = ((range(9000, 9100), _H), (range(9200, 9300), _C))
"""A program's own ``ERROR 9xxx``: 9000–9099 are H, 9200–9299 C, the rest L [DOC S1 ERROR]."""


def is_user_error(number: int) -> bool:
    """Whether ``number`` is one a program raises itself (``ERROR 9100``).

    >>> is_user_error(9100), is_user_error(2000)
    (True, False)
    """
    return number in USER_ERRORS


def error_level(number: int) -> ErrorLevel | None:
    """The level of `number`: the table's, a user error's by its range, else None."""
    info = ERROR_MESSAGES.get(number)
    if info is not None:
        return info.level
    for numbers, level in USER_ERROR_LEVELS:
        if number in numbers:
            return level
    return _L if number in USER_ERRORS else None


def error_code(number: int, level: ErrorLevel | None = None) -> str:
    """The number as the manual and the teaching pendant write it: ``L2000`` (level letter
    and four digits). The level defaults to `error_level`; ``2000`` when none is known.
    The one place the text form is made."""
    known = level if level is not None else error_level(number)
    digits = f"{number:04d}"
    return f"{known.letter}{digits}" if known is not None else digits


def error_text(number: int) -> str:
    """``"L6020 The Operation is disable"``, or a plain fallback for unknown numbers."""
    info = ERROR_MESSAGES.get(number)
    code = error_code(number)
    if info is None:
        return f"error {code} (not in melfa's table; see the controller manual BFP-A5993)"
    return f"{code} {info.message}"
