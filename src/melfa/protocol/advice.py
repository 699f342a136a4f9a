"""Controller errors in a student's words: what happened, what to do, and the one action
that fixes it, keyed by the controller's error number (the one home of these texts).

Built on `melfa.protocol.error_table` (numbers, levels, the controller's own terse texts):
this layer adds the sentence a first-year student can act on. Every frontend (web IDE,
desktop, CLI) shows `Advice.message`, keeps `Advice.code` (``L2000``) so the number can be
looked up in the manual, and offers `Advice.fix` as a button where one action fixes it.

>>> a = advice_for(2000)
>>> a.code, a.fix, a.fix_label
('L2000', <Fix.SERVO_ON_RETRY: 'servo-on-retry'>, 'Turn on and retry')
>>> a.message
'The servo is off, so the arm cannot move. Switch it on and try again.'
>>> advice_for(9999).code
'9999'
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from melfa.protocol.error_table import (
    BUSY,
    DURING_ERROR,
    ERROR_MESSAGES,
    ILLEGAL_COMMAND,
    JOG_REFUSED,
    JOINT_LIMIT,
    NO_RIGHTS,
    ORIGIN_NOT_SET,
    PROGRAM_BEING_EDITED,
    PROGRAM_NOT_FOUND,
    PROGRAM_RUNNING,
    SERVO_OFF,
    SERVO_ON_DURING_ERROR,
    SYNTAX,
    TB_ENABLED,
    VARIABLE_NOT_DEFINED,
    error_code,
    is_user_error,
)


class Fix(enum.Enum):
    """One action that fixes an error; frontends show it as a button (`FIX_LABELS`)."""

    SERVO_ON_RETRY = "servo-on-retry"
    """Switch the servo on, then repeat the refused command."""
    RESET_ALARM = "reset-alarm"
    LOAD_PROJECT = "load-project"
    ADD_POINT = "add-point"
    """Define the missing point from where the arm stands now."""
    STOP = "stop"
    TAKE_CONTROL = "take-control"


FIX_LABELS: dict[Fix, str] = {
    Fix.SERVO_ON_RETRY: "Turn on and retry",
    Fix.RESET_ALARM: "Reset alarm",
    Fix.LOAD_PROJECT: "Load project",
    Fix.ADD_POINT: "Add it from the current position",
    Fix.STOP: "Stop",
    Fix.TAKE_CONTROL: "Take control",
}


@dataclass(frozen=True)
class Advice:
    """``what`` happened and what ``todo``, the error ``code`` (``L2000``), the ``fix``."""

    what: str
    todo: str
    code: str
    fix: Fix | None = None

    @property
    def message(self) -> str:
        return f"{self.what} {self.todo}"

    @property
    def fix_label(self) -> str | None:
        return FIX_LABELS[self.fix] if self.fix is not None else None

    def to_json(self) -> dict[str, str | None]:
        """``{code, message, fix, fix_label}`` for the web API and the desktop client."""
        return {
            "code": self.code,
            "message": self.message,
            "fix": self.fix.value if self.fix is not None else None,
            "fix_label": self.fix_label,
        }


_REACH = (
    "The position is outside the robot's reach.",
    "Choose a point closer to the robot, or jog there and save it from where the arm stands.",
    None,
)
_POSITION = (
    "The position data is not valid for the robot.",
    "Check the point's six values and its two flags (FL1, FL2) in the Points tab.",
    None,
)

_TEXTS: dict[int, tuple[str, str, Fix | None]] = {
    SERVO_OFF: (
        "The servo is off, so the arm cannot move.",
        "Switch it on and try again.",
        Fix.SERVO_ON_RETRY,
    ),
    SERVO_ON_DURING_ERROR: (
        "The servo cannot be switched on while an alarm is active.",
        "Reset the alarm first.",
        Fix.RESET_ALARM,
    ),
    1640: (
        "The servo cannot be switched on: the pendant's enable (deadman) switch is off.",
        "Ask your instructor to check the teaching pendant.",
        None,
    ),
    DURING_ERROR: (
        "The controller has an active alarm and refuses to do anything else.",
        "Reset the alarm, then try again.",
        Fix.RESET_ALARM,
    ),
    BUSY: (
        "The robot is still busy: the arm is moving or a program is running.",
        "Wait until it has stopped, or press Stop.",
        Fix.STOP,
    ),
    PROGRAM_NOT_FOUND: (
        "There is no program in the controller yet.",
        "Load the project first.",
        Fix.LOAD_PROJECT,
    ),
    PROGRAM_BEING_EDITED: (
        "The controller is still receiving a program.",
        "Wait until the upload has finished, then try again.",
        None,
    ),
    PROGRAM_RUNNING: (
        "A program is running (or paused) on the controller.",
        "Stop it first.",
        Fix.STOP,
    ),
    NO_RIGHTS: (
        "The controller does not take commands from the computer right now.",
        "Check that the mode key is on AUTOMATIC (Ext.) and the pendant is disabled.",
        None,
    ),
    5010: (
        "The controller does not take commands from the computer right now.",
        "Check that the mode key is on AUTOMATIC (Ext.).",
        None,
    ),
    TB_ENABLED: (
        "The teaching pendant holds the controller.",
        "Switch the pendant's ENABLE key off.",
        None,
    ),
    ORIGIN_NOT_SET: (
        "The robot's origin has not been set.",
        "Ask your instructor: the origin is set once with the teaching pendant.",
        None,
    ),
    JOG_REFUSED: (
        "The controller did not accept the jog.",
        "Check that the servo is on and no alarm is active, then try again.",
        None,
    ),
    JOINT_LIMIT: (
        "A joint would pass its limit.",
        "Move the other way, or choose a point the arm can reach.",
        None,
    ),
    **dict.fromkeys(range(2180, 2194), _REACH),
    **dict.fromkeys(range(2600, 2604), _REACH),
    **dict.fromkeys(range(2800, 2804), _POSITION),
    3860: _POSITION,
    SYNTAX: (
        "The controller did not understand a statement (syntax error).",
        "Check the line in the editor; the problems list explains it.",
        None,
    ),
    VARIABLE_NOT_DEFINED: (
        "The program uses a point or variable that has no value.",
        "Define it in the Points tab (or assign it in the program) and load again.",
        None,
    ),
    3700: (
        "The program uses a point or variable before it has a value.",
        "Define it in the Points tab (or assign it in the program) and load again.",
        None,
    ),
    ILLEGAL_COMMAND: (
        "The controller did not accept this command.",
        "Check the robot's connection and mode key; ask your instructor if it stays.",
        None,
    ),
}


def advice_for(number: int) -> Advice:
    """What error ``number`` means for a student, with its fix if one action fixes it."""
    if is_user_error(number):
        return Advice(
            f"Your program stopped itself: its ERROR {number} statement ran.",
            "That is your own error, on the line the editor marks; reset the alarm to go on.",
            error_code(number),
            Fix.RESET_ALARM,
        )
    text = _TEXTS.get(number)
    if text is not None:
        what, todo, fix = text
        return Advice(what, todo, error_code(number), fix)
    info = ERROR_MESSAGES.get(number)
    what = (
        f"The controller refused: {info.message}."
        if info is not None
        else "The controller refused the command."
    )
    todo = "Look the code up in the controller manual, or ask your instructor."
    return Advice(what, todo, error_code(number), None)


__all__ = [
    "FIX_LABELS",
    "Advice",
    "Fix",
    "advice_for",
    "error_code",
    "is_user_error",
]
