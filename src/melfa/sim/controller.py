"""The virtual CR2B-574: one request line in, one reply out, no I/O and no clock.

`VirtualController.handle(request, now)` answers what the real controller answers, with the
same `melfa.protocol` code the client reads replies with, so the two cannot drift. `now`
(seconds, any origin, never decreasing) comes from the caller: servers pass a monotonic
clock, tests pass numbers. Motion happens on a `SimulatedArm` advanced to `now` before each
answer.

This module only dispatches. It finds the command in the protocol's one command table
(`melfa.protocol.commands`), checks what every request needs (OPEN first, only with
`open_required`: 6010; the operation rights and the MODE key: 6020; in strict mode, real
evidence: 6010), calls the
handler of the command (`melfa.sim.handlers`, one module per job) and writes the refusal in
the configured form (9 digits like a real CRn-5xx, or the manual's 4) and `Qok`/`Qer` while
an alarm is active. The state lives in `melfa.sim.core.ControllerCore`.

>>> from melfa.sim.config import SimConfig
>>> VirtualController(SimConfig(open_required=True)).handle(b"1;1;STATE\\r", now=0.0)
b'QeR601000000\\r'
>>> c = VirtualController()
>>> c.handle(b"1;1;OPEN=NARCUSR\\r", now=0.0)[:12]
b'QoK3F;3F;7,0'
>>> c.handle(b"1;1;SRVON\\r", now=0.1)
b'QeR602000000\\r'
"""

from __future__ import annotations

from melfa.protocol.commands import COMMANDS, CommandSpec, Evidence, SlotForm
from melfa.protocol.commands import lookup as lookup_spec
from melfa.protocol.error_table import ErrorCode
from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.messages import (
    EditRefused,
    Ok,
    Refused,
    Reply,
    Request,
    encode_reply,
    parse_request,
)
from melfa.sim import errors as err
from melfa.sim.config import KeySwitch
from melfa.sim.core import ControllerCore
from melfa.sim.handlers import HANDLERS, SUPPORTED_COMMANDS
from melfa.sim.runner import StepError

_SLOT_RESET = frozenset({"SLOTINIT", "RSTPRG"})

STRICT_EVIDENCE = frozenset({Evidence.TRACE, Evidence.CLIENT})
"""What strict mode serves: commands a real controller answered on record, or that real
serial clients (the thesis, RT ToolBox, gerrard, ctu-mitsubishi) send to one."""

DETAIL_DIGITS = "00000"
"""The 5 digits after the error number in a 9-digit refusal: all refusals on record have
`00000` (`QeR602000000`, `QeR512000000`, `Qer515000000`) [TRACE K9b]."""

__all__ = ["STRICT_EVIDENCE", "SUPPORTED_COMMANDS", "VirtualController", "strict_commands"]


def strict_commands() -> tuple[str, ...]:
    """The command words strict mode answers (listed in docs/simulator.md)."""
    return tuple(n for n in SUPPORTED_COMMANDS if COMMANDS[n].evidence in STRICT_EVIDENCE)


class VirtualController(ControllerCore):
    """The sans-I/O simulated CR2B-574 (state and hooks: see `ControllerCore`)."""

    def handle(self, request: bytes | str, now: float) -> bytes:
        """Answer one request line (with or without its CR) at time `now`."""
        return encode_reply(self.respond(request, now), self.config.cterm.wire)

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
            return self._finish(Refused(number))
        spec = lookup_spec(parsed.command)
        handler = HANDLERS.get(spec.name) if spec is not None else None
        if spec is None or handler is None:
            return self._finish(Refused(err.ILLEGAL_COMMAND))
        refusal = self._admit(spec, parsed)
        if refusal is not None:
            return self._finish(Refused(refusal))
        argument = parsed.command[len(spec.name) :]
        try:
            reply = handler(self, argument, parsed, now)
        except StepError as step:
            self.raise_alarm(step.number, now)
            reply = Refused(step.number)
        return self._finish(reply)

    def _admit(self, spec: CommandSpec, req: Request) -> int | None:
        """The error number that refuses `req` before its handler runs, or None."""
        if spec.name != "OPEN=" and not self.is_open and self.config.open_required:
            return err.ILLEGAL_COMMAND
        if self.config.strict and (
            spec.evidence not in STRICT_EVIDENCE or self._slot_form(req) not in spec.slots
        ):
            return err.ILLEGAL_COMMAND
        slot_reset = spec.name in _SLOT_RESET
        if spec.rights and self.key is not KeySwitch.AUTO_EXT:
            # [TRACE K9b-PROG] SLOTINIT in TEACH: QeR602000000 although CNTLON got QoK.
            return err.NO_RIGHTS
        needs_rights = spec.rights and (not slot_reset or self.config.rights_for_slot_reset)
        if needs_rights and not self.rights:
            return err.NO_RIGHTS
        return None

    def _slot_form(self, req: Request) -> SlotForm:
        if req.slot == 0:
            return SlotForm.ALL
        if req.slot < 0:
            return SlotForm.CURRENT
        if req.slot == self.config.banner.taskmax + 1:
            return SlotForm.EDIT
        return SlotForm.TASK

    def refuse(self, number: int) -> Reply:
        """The refusal `number` as this controller writes it (servers' framing errors)."""
        return self._finish(Refused(number))

    def _finish(self, reply: Reply) -> Reply:
        """Mark the reply while an alarm is active and write refusals in the set form."""
        alarm = self.alarm is not None
        detail = DETAIL_DIGITS if self.config.nine_digit_errors else None
        if isinstance(reply, Ok):
            return Ok(reply.answer, alarm)
        if isinstance(reply, Refused):
            return Refused.of(ErrorCode(reply.error, detail), alarm=alarm)
        if isinstance(reply, EditRefused):
            return EditRefused(reply.error, reply.item, reply.column, reply.alarm, detail)
        return reply
