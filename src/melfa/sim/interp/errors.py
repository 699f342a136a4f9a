"""Run-time errors of a MELFA BASIC IV program, with the controller's error numbers.

A program that fails stops with the number the CR2B-574 would show (STATE, ERROR,
the teach pendant) and the line it failed on. Numbers come from the troubleshooting
manual BFP-A5993-M as listed in ``melfa-basic-iv.md`` §8 and ``protocol.md`` §2.3 [DOC];
the ones no public list gives are [GUESS] constants below, named so they can be
corrected in one place once checked on the real controller.
"""

from __future__ import annotations

from melfa.lang import model as lang_model
from melfa.protocol.error_table import (
    ARGUMENT_OUT_OF_RANGE,
    ARRAY_ELEMENT,
    DIVISION_BY_ZERO,
    DUPLICATE_DEFINITION,
    ERROR_MESSAGES,
    FOR_NEXT_UNMATCH,
    GOSUB_NESTING_OVER,
    IF_ELSE_UNMATCH,
    IF_ENDIF_UNMATCH,
    ILLEGAL_POSITION,
    ILLEGAL_POSITION_DATA,
    JOINT_LIMIT,
    JUMP_DESTINATION_MISSING,
    LINE_NOT_FOUND,
    LINE_NUMBER_RANGE,
    NESTING_OVER,
    NUMERIC_OVERFLOW,
    POSITION_LIMIT,
    RETURN_WITHOUT_GOSUB,
    SELECT_UNMATCH,
    SERVO_OFF,
    STATEMENT_TOO_LONG,
    TYPE_COMBINATION,
    UNDEFINED_PALLET,
    UNDEFINED_VARIABLE,
    VARIABLE_NOT_DEFINED,
    WHILE_WEND_UNMATCH,
    XYZ_LIMIT,
    ErrorLevel,
    error_code,
    error_level,
)
from melfa.protocol.error_table import SYNTAX as SYNTAX_ERROR
from melfa.sim.runner import RunnerError, StepError

# The numbers are the controller's, named once in `melfa.protocol.error_table`; the
# interpreter raises them by these names (``errors.UNDEFINED_VARIABLE``).

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
        super().__init__(number, message, level=lvl)
        self.error_level = lvl
        self.line = line

    @property
    def code(self) -> str:
        """The number with its level letter, as in the manual (``L3700``)."""
        return error_code(self.number, self.level)

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
    return f"{error_code(error.number, error.level)}{where}: {error.message}"


def level_for(number: int) -> ErrorLevel:
    """The level of our numbers: the controller's table, user ``ERROR 9xxx`` by range
    (`melfa.protocol.error_table.error_level`), else L."""
    return error_level(number) or ErrorLevel.LOW


def error_text(error: RunnerError) -> str:
    """``L3700 Undefined (uninitialised) variable (variable M9 has no value)``: the
    controller's number and message, then what the simulator found."""
    code = error_code(error.number, error.level)
    known = ERROR_MESSAGES.get(error.number)
    if known is None or known.message == error.message:
        return f"{code} {error.message}"
    return f"{code} {known.message} ({error.message})"


__all__ = [
    "ARGUMENT_OUT_OF_RANGE",
    "ARRAY_ELEMENT",
    "DIVISION_BY_ZERO",
    "DUPLICATE_DEFINITION",
    "FOR_NEXT_UNMATCH",
    "GOSUB_NESTING_OVER",
    "IF_ELSE_UNMATCH",
    "IF_ENDIF_UNMATCH",
    "ILLEGAL_POSITION",
    "ILLEGAL_POSITION_DATA",
    "JOINT_LIMIT",
    "JUMP_DESTINATION_MISSING",
    "LINE_NOT_FOUND",
    "LINE_NUMBER_RANGE",
    "MAX_GOSUB_DEPTH",
    "MAX_LOOP_DEPTH",
    "NESTING_OVER",
    "NOT_SUPPORTED",
    "NUMERIC_OVERFLOW",
    "POSITION_LIMIT",
    "RETURN_WITHOUT_GOSUB",
    "SELECT_UNMATCH",
    "SERVO_OFF",
    "STATEMENT_TOO_LONG",
    "SYNTAX_ERROR",
    "TYPE_COMBINATION",
    "UNDEFINED_PALLET",
    "UNDEFINED_VARIABLE",
    "UNREACHABLE",
    "VARIABLE_NOT_DEFINED",
    "WHILE_WEND_UNMATCH",
    "XYZ_LIMIT",
    "ErrorLevel",
    "RunError",
    "describe",
    "error_text",
    "level_for",
]
