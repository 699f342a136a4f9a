"""Controller error numbers with their level letter and message.

From BFP-A5993-M (S4) as quoted in protocol.md §2.3 and melfa-basic-iv.md §8. Replies carry
the number without its letter (``QeR6020`` is L6020). The robot client prefers the
controller's own text (``ERRORMES<n>``) and falls back to this table.

>>> ERROR_MESSAGES[6020]
ErrorInfo(level='L', message='The Operation is disable')
>>> error_text(6020)
'L6020 The Operation is disable'
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType
from typing import NamedTuple


class ErrorInfo(NamedTuple):
    """Level letter (H high: servo off, L low: operation stops, C caution) and message."""

    level: str
    message: str


_TABLE: dict[int, ErrorInfo] = {
    # protocol.md §2.3
    6010: ErrorInfo("L", "Illegal command"),
    6020: ErrorInfo("L", "The Operation is disable"),
    5640: ErrorInfo("L", "Cannot execute during RUN"),
    5600: ErrorInfo("L", "Cannot execute during an error"),
    5010: ErrorInfo("L", "AUTOENA signal is OFF"),
    1630: ErrorInfo("C", "Cannot servo ON during an error"),
    1640: ErrorInfo("C", "Cannot servo ON: DEADMAN OFF"),
    2000: ErrorInfo("L", "The servo is OFF"),
    2030: ErrorInfo("L", "JOG operation cannot be accepted"),
    2160: ErrorInfo("H", "Joint angle exceeds the limit"),
    **{n: ErrorInfo("H", "X/Y/Z data exceeds the limit") for n in range(2180, 2194)},
    **{n: ErrorInfo("L", "Position data exceeds the limit") for n in range(2600, 2604)},
    **{n: ErrorInfo("L", "Illegal position data") for n in range(2800, 2804)},
    3270: ErrorInfo("L", "The command size is exceeded (256 single-byte characters)"),
    4140: ErrorInfo("L", "The program was not found"),
    4170: ErrorInfo("L", "The program is being edited"),
    4180: ErrorInfo("L", "Program is running"),
    4220: ErrorInfo("L", "Syntax error"),
    4230: ErrorInfo("L", "The line No. does not exist"),
    4300: ErrorInfo("L", "Variable name too long (max 8 characters)"),
    4340: ErrorInfo("L", "The variable is not defined"),
    6080: ErrorInfo("C", "Com mesg is too long"),
    # melfa-basic-iv.md §8
    3220: ErrorInfo("L", "Nesting over (IF/FOR)"),
    3230: ErrorInfo("L", "FOR/NEXT unmatch"),
    3240: ErrorInfo("L", "FOR/WHILE nesting exceeds 16"),
    3250: ErrorInfo("L", "WHILE/WEND unmatch"),
    3251: ErrorInfo("L", "More than 32 jump destinations (ON GOTO)"),
    3252: ErrorInfo("L", "IF/ENDIF unmatch"),
    3253: ErrorInfo("L", "IF nesting exceeds 8"),
    3254: ErrorInfo("L", "SELECT/END SELECT unmatch"),
    3255: ErrorInfo("L", "IF/ELSE unmatch"),
    3600: ErrorInfo("L", "Jump destination missing"),
    3700: ErrorInfo("L", "Undefined (uninitialised) variable"),
    3840: ErrorInfo("L", "RETURN without GOSUB"),
    3850: ErrorInfo("L", "Undefined PLT"),
    3860: ErrorInfo("L", "Illegal position data"),
    4120: ErrorInfo("L", "Illegal program name"),
    4130: ErrorInfo("L", "Illegal program name"),
    4210: ErrorInfo("L", "Statement longer than 127 characters"),
    4310: ErrorInfo("L", "Illegal character"),
    4350: ErrorInfo("L", "Duplicate definition"),
    4370: ErrorInfo("L", "Array element error"),
    4390: ErrorInfo("L", "Variable type combination"),
    4420: ErrorInfo("L", "Line No. exceeds 32767"),
    4440: ErrorInfo("L", "Duplicate label"),
    4910: ErrorInfo("L", "RLNG mismatch (1 = MELFA-BASIC IV, 0 = MOVEMASTER)"),
}

ERROR_MESSAGES: Mapping[int, ErrorInfo] = MappingProxyType(_TABLE)
"""Error number -> (level letter, message). Read-only."""


def error_text(number: int) -> str:
    """``"L6020 The Operation is disable"``, or a plain fallback for unknown numbers."""
    info = ERROR_MESSAGES.get(number)
    if info is None:
        return f"error {number:04d} (not in melfa's table; see the controller manual BFP-A5993)"
    return f"{info.level}{number:04d} {info.message}"
