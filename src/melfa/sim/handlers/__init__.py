"""The virtual controller's request handlers, one module per job.

- `session`: OPEN/CLOSE, operation rights, KEYWD, PRTVER, parameters.
- `programs`: program memory and the edit slot (NEW/LOAD/EMDAT/SAVE/LIST…/PDIR/FDEL) and the
  task slots (PRGLOAD/RUN/RSTPRG/SLOTINIT).
- `motion`: servo, override, jog, EXEC, hand, STOP, the I/O signals.
- `state`: STATE/DSTATE, positions, alarms and the error log, clock, small read-only answers.

Each handler is `(controller, argument, request, now) -> Reply`, keyed by its name in the
protocol's one command table (`melfa.protocol.commands`), which says what each command
needs (rights, argument or none, slot forms) and how sure we are the real one answers it.
"""

from __future__ import annotations

from melfa.protocol.commands import COMMANDS
from melfa.sim.core import Handler
from melfa.sim.handlers import motion, programs, session, state

HANDLERS: dict[str, Handler] = {
    **session.HANDLERS,
    **state.HANDLERS,
    **motion.HANDLERS,
    **programs.HANDLERS,
}
_unknown = set(HANDLERS) - set(COMMANDS)
assert not _unknown, f"handlers for commands the protocol table does not know: {_unknown}"

SUPPORTED_COMMANDS: tuple[str, ...] = tuple(HANDLERS)
"""Every command word the virtual controller answers (prefixes for those with arguments)."""
