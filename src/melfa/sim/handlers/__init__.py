"""The virtual controller's request handlers, one module per job, and the one command table.

- `session`: OPEN/CLOSE, operation rights, KEYWD, PRTVER, parameters.
- `programs`: program memory and the edit slot (NEW/LOAD/EMDAT/SAVE/LIST…/PDIR/FDEL) and the
  task slots (PRGLOAD/RUN/RSTPRG/SLOTINIT).
- `motion`: servo, override, jog, EXEC, hand, STOP, the I/O signals.
- `state`: STATE/DSTATE, positions, alarms and the error log, small read-only answers.

Each handler is `(controller, argument, request, now) -> Reply`; `lookup` finds the command
of a request text (longest word first; `exact` words take no argument).
"""

from __future__ import annotations

from melfa.sim.core import Command
from melfa.sim.handlers import motion, programs, session, state

TABLE: tuple[Command, ...] = (
    *session.COMMANDS,
    *state.COMMANDS,
    *motion.COMMANDS,
    *programs.COMMANDS,
)
_BY_LENGTH = sorted(TABLE, key=lambda c: len(c.name), reverse=True)

SUPPORTED_COMMANDS: tuple[str, ...] = tuple(c.name for c in TABLE)
"""Every command word the virtual controller answers (prefixes for those with arguments)."""


def lookup(text: str) -> Command | None:
    """The command a request's text starts with, or None (an illegal command)."""
    upper = text.upper()
    for command in _BY_LENGTH:
        if upper.startswith(command.name):
            if command.exact and upper[len(command.name) :].strip():
                continue
            return command
    return None
