"""The words about the controller's program slot: whose program it holds, the question a
*Run* asks when that is not the text in your editor, a run-time error on its line, and a
run stopped because its holder's pages closed.

Templates with ``{user}``, ``{time}`` (the browser's local time), ``{workspace}``,
``{code}`` and ``{line}``; the browser gets them in ``/vocab.js`` as ``SLOT_WORDS``.
"""

from __future__ import annotations

SLOT_WORDS: dict[str, str] = {
    "empty": "No program melfa knows of is in the robot",
    "mine": "Your program is in the robot (loaded {time})",
    "mine_changed": "Your program of {time} is in the robot; your editor has changed since",
    "theirs": "{user}'s program is in the robot (loaded {time}{from})",
    "from": " from {workspace}",
    "chip_empty": "No known program",
    "chip_mine": "Your program",
    "chip_mine_changed": "Your older text",
    "chip_theirs": "{user}'s program",
    "ask_title_theirs": "Run {user}'s program?",
    "ask_theirs": "The robot holds {user}'s program, loaded at {time}{from}, not the text in "
    "your editor. Run moves the arm with their program.",
    "ask_title_changed": "Run the program you loaded at {time}?",
    "ask_changed": "Your editor has changed since you loaded it: the robot would run the "
    "older text, and its lines would not match your editor's.",
    "ask_title_unknown": "Run whatever the robot holds?",
    "ask_unknown": "melfa does not know which program the robot holds: nothing was loaded "
    "since the server started, or the last load did not finish.",
    "run_theirs": "Run {user}'s program",
    "run_old": "Run the loaded one",
    "run_unknown": "Run it anyway",
    "load_mine": "Load mine, then run",
    "program_error": "Error {code} at line {line}",
    "program_error_theirs": "Error {code} at line {line} of {user}'s program",
    "program_error_step": "Error {code} at the line numbered {step}",
    "stopped_when_left_title": "Your run was stopped",
    "stopped_when_left": "Your run was stopped at {time} because every page of yours had "
    "closed (a reload or a closed tab stops the robot, for safety).",
}
"""Every sentence about the slot, by key. The ``chip_`` words are what the 3D view's narrow
head shows (whose, first); the whole sentence is its tooltip and accessible name."""


__all__ = ["SLOT_WORDS"]
