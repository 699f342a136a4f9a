"""Controller error numbers the virtual controller answers with.

Numbers from BFP-A5993-M (S4) as listed in protocol.md §2.3 and melfa-basic-iv.md §8 [DOC];
texts come from `melfa.protocol.error_table` (one table for client and simulator). Numbers
no public source gives for a situation are [GUESS] and say so.
"""

from __future__ import annotations

from typing import Final

ILLEGAL_COMMAND: Final = 6010  # L6010: before OPEN, or unknown to this firmware [DOC S4]
NO_RIGHTS: Final = 6020  # L6020 "The Operation is disable": CNTLON missing [DOC S4]
COMMAND_TOO_LONG: Final = 6080  # C6080 "Com mesg is too long" [DOC S4]
BUSY: Final = 5640  # L5640 "Cannot execute during RUN" [DOC S4; CODE S6/S7 busy test]
DURING_ERROR: Final = 5600  # L5600 "Cannot execute during an error" [DOC S4]
SERVO_ON_DURING_ERROR: Final = 1630  # C1630 cannot servo ON during an error [DOC S4]
SERVO_OFF: Final = 2000  # L2000 "The servo is OFF" [DOC S4]
JOG_REFUSED: Final = 2030  # L2030 "JOG operation cannot be accepted" [DOC S4]
JOINT_LIMIT: Final = 2160  # H2160 "Joint angle exceeds the limit" [DOC S4]
PROGRAM_NOT_FOUND: Final = 4140  # L4140 [DOC S4]
PROGRAM_BEING_EDITED: Final = 4170  # L4170 [DOC S4]
PROGRAM_RUNNING: Final = 4180  # L4180 "Program is running" [DOC S4]
SYNTAX: Final = 4220  # L4220 [DOC S4]
VARIABLE_NOT_DEFINED: Final = 4340  # L4340 [DOC S4]
BAD_PROGRAM_NAME: Final = 4120  # L4120 program name [melfa-basic-iv.md §8]

ARGUMENT_OUT_OF_RANGE: Final = 3110
"""[GUESS] OVRD=0, HNDON9 … : no public list names the error; same number as the
interpreter's `ARGUMENT_OUT_OF_RANGE` so both sides agree."""

PARAMETER_NOT_FOUND: Final = 6010
"""[GUESS] PAR<name> of a parameter the simulator does not know: answered as illegal."""

NOT_EDITING: Final = 6010
"""[GUESS] EMDAT/EDATA with no program open (no LOAD=): answered as illegal."""
