"""The virtual CR2B-574: one request line in, one reply out, no I/O and no clock.

`VirtualController.handle(request, now)` answers what the real controller answers, with the
same `melfa.protocol` code the client reads replies with, so the two cannot drift. `now`
(seconds, any origin, never decreasing) comes from the caller: servers pass a monotonic
clock, tests pass numbers. Motion happens on a `SimulatedArm` advanced to `now` before each
answer.

This module only dispatches: it checks what every request needs (OPEN first: 6010; the
operation rights: 6020), calls the handler of the command (`melfa.sim.handlers`, one module
per job) and marks replies while an alarm is active (`Qok`/`Qer`). The state lives in
`melfa.sim.core.ControllerCore`.

>>> c = VirtualController()
>>> c.handle(b"1;1;STATE\\r", now=0.0)
b'QeR6010\\r'
>>> c.handle(b"1;1;OPEN=NARCUSR\\r", now=0.0)[:12]
b'QoK3F;3F;7,0'
>>> c.handle(b"1;1;SRVON\\r", now=0.1)
b'QeR6020\\r'
"""

from __future__ import annotations

from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.messages import Ok, Refused, Reply, encode_reply, parse_request
from melfa.sim import errors as err
from melfa.sim.core import ControllerCore
from melfa.sim.handlers import SUPPORTED_COMMANDS, TABLE, lookup
from melfa.sim.runner import StepError

# Commands that need the operation rights [DOC S1/S2 §5.1, the `*` list], plus RSTALRM
# [DOC S5]. SRVOFF and STOP never need them [DOC S5].
_RIGHTS_DOC = frozenset(
    {"EXEC", "STEP", "PRGLOAD=", "LINENO=", "SRVON", "OVRD=", "RUN", "JOG", "RSTALRM"}
)
_SLOT_RESET = frozenset({"SLOTINIT", "RSTPRG"})
assert all(c.rights == (c.name in _RIGHTS_DOC) for c in TABLE), "rights table drifted"

__all__ = ["SUPPORTED_COMMANDS", "VirtualController"]


class VirtualController(ControllerCore):
    """The sans-I/O simulated CR2B-574 (state and hooks: see `ControllerCore`)."""

    def handle(self, request: bytes | str, now: float) -> bytes:
        """Answer one request line (with or without its CR) at time `now`."""
        return encode_reply(self.respond(request, now))

    def respond(self, request: bytes | str, now: float) -> Reply:
        """Like `handle`, as a typed reply."""
        self.advance(now)
        now = self.now
        data = request.encode("latin-1", "replace") if isinstance(request, str) else request
        try:
            parsed = parse_request(data)
        except RemoteProtocolError as exc:
            number = exc.error_number or err.ILLEGAL_COMMAND
            if number == err.COMMAND_TOO_LONG:
                number = self.config.too_long_error
            return self._refuse(number)
        text = parsed.command
        command = lookup(text)
        if command is None:
            return self._refuse(err.ILLEGAL_COMMAND)
        if command.needs_open and not self.is_open:
            return self._refuse(err.ILLEGAL_COMMAND)
        needs_rights = command.rights or (
            command.name in _SLOT_RESET and self.config.rights_for_slot_reset
        )
        if needs_rights and not self.rights:
            return self._refuse(err.NO_RIGHTS)
        argument = text[len(command.name) :]
        try:
            reply = command.handler(self, argument, parsed, now)
        except StepError as step:
            self.raise_alarm(step.number, now)
            reply = Refused(step.number)
        return self._with_alarm(reply)

    def _refuse(self, number: int) -> Reply:
        return self._with_alarm(Refused(number))

    def _with_alarm(self, reply: Reply) -> Reply:
        alarm = self.alarm is not None
        if isinstance(reply, Ok):
            return Ok(reply.answer, alarm)
        if isinstance(reply, Refused):
            return Refused(reply.error, alarm)
        return reply
