"""Run-time errors of a MELFA BASIC IV program, with the controller's error numbers.

A program that fails stops with the number the CR2B-574 would show (STATE, ERROR,
the teach pendant) and the line it failed on. Numbers come from the troubleshooting
manual BFP-A5993-M as listed in ``melfa-basic-iv.md`` §8 and ``protocol.md`` §2.3 [DOC];
the ones no public list gives are [GUESS] constants below, named so they can be
corrected in one place once checked on the real controller.
"""

from __future__ import annotations

import enum

from melfa.lang import model as lang_model
from melfa.protocol.error_table import ERROR_MESSAGES
from melfa.sim.runner import RunnerError, StepError


class ErrorLevel(enum.Enum):
    """H = high (servo off), L = low (operation stops), C = caution (continues)."""

    HIGH = "H"
    LOW = "L"
    CAUTION = "C"


# --- numbers from the documents [DOC S3 via melfa-basic-iv.md §8, protocol.md §2.3] -----------
SERVO_OFF = 2000  # L2000 "The servo is OFF"
JOINT_LIMIT = 2160  # H2160 "Joint angle exceeds the limit"
XYZ_LIMIT = 2180  # H2180-H2193 "X/Y/Z data exceeds the limit"
POSITION_LIMIT = 2600  # L2600-L2603 "Position data exceeds the limit"
ILLEGAL_POSITION_DATA = 2800  # L2800-L2803 "Illegal position data"
FOR_NEXT_UNMATCH = 3230  # L3230
NESTING_OVER = 3240  # L3240 FOR/WHILE nesting > 16
WHILE_WEND_UNMATCH = 3250  # L3250
IF_ENDIF_UNMATCH = 3252  # L3252
SELECT_UNMATCH = 3254  # L3254
IF_ELSE_UNMATCH = 3255  # L3255
JUMP_DESTINATION_MISSING = 3600  # L3600 "Jump destination does not exist"
UNDEFINED_VARIABLE = 3700  # L3700 referencing a variable never initialised
RETURN_WITHOUT_GOSUB = 3840  # L3840
UNDEFINED_PALLET = 3850  # L3850 undefined PLT
ILLEGAL_POSITION = 3860  # L3860 illegal position data
SYNTAX_ERROR = 4220  # L4220
LINE_NOT_FOUND = 4230  # L4230 "The line No. does not exist"
VARIABLE_NOT_DEFINED = 4340  # L4340
DUPLICATE_DEFINITION = 4350  # L4350 redefinition with DIM/DEF
ARRAY_ELEMENT = 4370  # L4370 array element error (subscript out of range)
TYPE_COMBINATION = 4390  # L4390 variable type combination

# --- [GUESS] numbers: no public error list gives them ------------------------------------------
#: [GUESS] division by zero ([S2 p.164] says it is an error but not which number).
DIVISION_BY_ZERO = 3500
#: [GUESS] a value outside what a statement/function accepts (OVRD 0, hand 9, SQR(-1) ...).
ARGUMENT_OUT_OF_RANGE = 3110
#: [GUESS] DEF INTE overflow (value outside -32768..32767) and real overflow.
NUMERIC_OVERFLOW = 3120
#: [GUESS] GOSUB nested deeper than the controller allows (about 800 [S2c]).
GOSUB_NESTING_OVER = 3220
#: [GUESS] a statement the simulator does not run (CALLP, files, multitask ...). Reported as
#: a syntax error so the controller's STATE shows a number; the message says why.
NOT_SUPPORTED = SYNTAX_ERROR
#: [GUESS] the target position cannot be reached (outside the work envelope). The controller
#: reports position errors in the L2600/H2180 family; kin may give a more exact number.
UNREACHABLE = POSITION_LIMIT

#: Nesting limits are the language's (`melfa.lang.model`, one home with the checker).
MAX_GOSUB_DEPTH = lang_model.MAX_GOSUB_DEPTH
MAX_LOOP_DEPTH = lang_model.MAX_LOOP_DEPTH


class RunError(StepError):
    """A run-time error raised while executing a statement; stops the program.

    It is the controller's `StepError` (so EXEC refusals and program errors are one type);
    `line` is filled in by the interpreter when it knows which step was executing.
    """

    def __init__(
        self,
        number: int,
        message: str,
        *,
        level: ErrorLevel | None = None,
        line: int | None = None,
    ) -> None:
        lvl = level if level is not None else level_for(number)
        super().__init__(number, message, level=lvl.value)
        self.error_level = lvl
        self.line = line

    @property
    def code(self) -> str:
        """The number with its level letter, as in the manual (``L3700``)."""
        return f"{self.level}{self.number:04d}"

    def to_error(self, line: int | None = None) -> RunnerError:
        return RunnerError(
            self.number, self.message, self.line if self.line is not None else line, self.level
        )

    def __str__(self) -> str:
        where = f" in line {self.line}" if self.line is not None else ""
        return f"{self.code}{where}: {self.message}"


def describe(error: RunnerError) -> str:
    """One line for people: ``L3700 in line 40: variable M9 has no value``."""
    where = f" in line {error.line}" if error.line is not None else ""
    return f"{error.level}{error.number:04d}{where}: {error.message}"


def level_for(number: int) -> ErrorLevel:
    """Level letter for our numbers: motion-limit errors are H, user 9xxx by range [S1 ERROR]."""
    if number == JOINT_LIMIT or 2180 <= number <= 2193:
        return ErrorLevel.HIGH
    if 9000 <= number <= 9099:
        return ErrorLevel.HIGH
    if 9200 <= number <= 9299:
        return ErrorLevel.CAUTION
    return ErrorLevel.LOW


def error_text(error: RunnerError) -> str:
    """``L3700 Undefined (uninitialised) variable (variable M9 has no value)``: the
    controller's number and message, then what the simulator found."""
    code = f"{error.level}{error.number:04d}"
    known = ERROR_MESSAGES.get(error.number)
    if known is None or known.message == error.message:
        return f"{code} {error.message}"
    return f"{code} {known.message} ({error.message})"
