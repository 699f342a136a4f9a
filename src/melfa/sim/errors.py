"""Controller error numbers the virtual controller answers with.

The numbers, their levels and texts live in `melfa.protocol.error_table` (one home for
client and simulator); this module only names the simulator's own [GUESS] choices.
"""

from __future__ import annotations

from typing import Final

from melfa.protocol.error_table import (
    ARGUMENT_OUT_OF_RANGE,
    BAD_PROGRAM_NAME,
    BUSY,
    COMMAND_TOO_LONG,
    DURING_ERROR,
    ILLEGAL_COMMAND,
    JOG_REFUSED,
    JOINT_LIMIT,
    NO_RIGHTS,
    PROGRAM_BEING_EDITED,
    PROGRAM_NOT_FOUND,
    PROGRAM_RUNNING,
    SERVO_OFF,
    SERVO_ON_DURING_ERROR,
    SYNTAX,
    VARIABLE_NOT_DEFINED,
)

PARAMETER_NOT_FOUND: Final = ILLEGAL_COMMAND
"""[GUESS] PAR<name> of a parameter the simulator does not know: answered as illegal."""

NOT_EDITING: Final = ILLEGAL_COMMAND
"""[GUESS] EMDAT/EDATA with no program open (no LOAD=): answered as illegal."""

__all__ = [
    "ARGUMENT_OUT_OF_RANGE",
    "BAD_PROGRAM_NAME",
    "BUSY",
    "COMMAND_TOO_LONG",
    "DURING_ERROR",
    "ILLEGAL_COMMAND",
    "JOG_REFUSED",
    "JOINT_LIMIT",
    "NOT_EDITING",
    "NO_RIGHTS",
    "PARAMETER_NOT_FOUND",
    "PROGRAM_BEING_EDITED",
    "PROGRAM_NOT_FOUND",
    "PROGRAM_RUNNING",
    "SERVO_OFF",
    "SERVO_ON_DURING_ERROR",
    "SYNTAX",
    "VARIABLE_NOT_DEFINED",
]
