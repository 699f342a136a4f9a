"""What moves or drives the arm: servo, override, jog, EXEC, hand, STOP, I/O signals.

Every motion is refused while an alarm is active (L5600) or while something else moves the
arm (L5640); STOP needs no rights and always answers [DOC S5].
"""

from __future__ import annotations

from melfa.protocol.answers import HandStatus
from melfa.protocol.error_table import ORIGIN_NOT_SET
from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.jog import Jog
from melfa.protocol.limits import HANDS, OVERRIDE_PERCENT
from melfa.protocol.messages import Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.core import ControllerCore, Handler, JogState, Slot
from melfa.sim.machine import ArmFault
from melfa.sim.runner import StatementExecutor

ALARM_BLOCKS = err.DURING_ERROR
"""L5600 "Cannot execute during an error": motion commands while an alarm is active [DOC S4]."""

IO_WORD_BITS = 16
"""[GUESS] `IN<n>` / `OUT<n>` answer 16 signals from bit n as 4 hex digits, the width of
`OUT=<n>;<hex4>` [protocol.md §3.10 gives the commands, not the answers]."""

# ------------------------------------------------------------------------ servo, override


def srvon(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.alarm is not None:
        return Refused(err.SERVO_ON_DURING_ERROR)
    c.arm.set_servo(True, now)
    return Ok()


def srvoff(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.jogging = None
    c.arm.stop(now)
    c.arm.set_servo(False, now)
    return Ok()


def ovrd_set(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    value = arg.strip()
    if not value.isdigit() or int(value) not in OVERRIDE_PERCENT:
        return Refused(err.ARGUMENT_OUT_OF_RANGE)
    c.arm.set_op_override(int(value), now)
    return Ok(str(int(value)))


# ---------------------------------------------------------------------------- signals


def _signal_bit(text: str) -> int | None:
    value = text.strip()
    return int(value) if value.isdigit() else None


def in_(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    bit = _signal_bit(arg)
    if bit is None:
        return Refused(err.ILLEGAL_COMMAND)
    return Ok(f"{c.io.read_inputs(bit, IO_WORD_BITS):04X}")


def out_get(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    bit = _signal_bit(arg)
    if bit is None:
        return Refused(err.ILLEGAL_COMMAND)
    return Ok(f"{c.io.read_outputs(bit, IO_WORD_BITS):04X}")


def out_set(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # `OUT=<n>;<hex4>` [protocol.md §3.10]: 16 output signals from n.
    start, _, value = arg.partition(";")
    bit = _signal_bit(start)
    try:
        word = int(value.strip(), 16)
    except ValueError:
        return Refused(err.ILLEGAL_COMMAND)
    if bit is None or not 0 <= word <= 0xFFFF:
        return Refused(err.ILLEGAL_COMMAND)
    c.io.write_outputs(bit, IO_WORD_BITS, word)
    return Ok()


# ------------------------------------------------------------------------------- hand


def _hand(c: ControllerCore, arg: str, on: bool, now: float) -> Reply:
    value = arg.strip()
    if not value.isdigit() or int(value) not in HANDS:
        return Refused(err.ARGUMENT_OUT_OF_RANGE)
    opened = on == c.config.hand_on_opens
    c.arm.set_hand(int(value), opened, now)
    return Ok()


def hndon(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    return _hand(c, arg, True, now)


def hndoff(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    return _hand(c, arg, False, now)


def hndsts(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [DOC S1 §5.2.56] 8 x `<signal no>;<1 open, 2 closed>;<0 single / 1 double>`,
    # e.g. `900;2;1;902;1;1;…`: hand n uses output signals 900 + 2(n-1).
    return Ok(HandStatus(tuple(c.arm.hand_open(hand) for hand in HANDS)).to_answer())


# ----------------------------------------------------------------------- EXEC, jog, stop


def exec_(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    statement = arg.strip()
    if c.origin_lost(now):
        return Refused(ORIGIN_NOT_SET)
    if c.alarm is not None:
        return Refused(ALARM_BLOCKS)
    # [CODE S6/S7] any EXEC while the arm still moves is refused with 5640; S6 uses
    # `EXECREM Waiting...` as its busy test.
    if c.moving or c.program_running:
        return Refused(err.BUSY)
    slot = c.slot(req)
    if c.config.exec_needs_program and slot.program is None and req.slot != 9:
        return Refused(err.PROGRAM_NOT_FOUND)
    executor = _executor_for(c, slot)
    if executor is None:
        return Refused(err.ILLEGAL_COMMAND)
    c.jogging = None
    executor.execute(statement, now)
    return Ok()


def _executor_for(c: ControllerCore, slot: Slot) -> StatementExecutor | None:
    """EXEC runs in the slot's program (its variables) when one is loaded [DOC S1
    §5.2.16: "in the task slot"], else in a bare interpreter; `executor=` overrides."""
    if c.executor is not None:
        return c.executor
    if isinstance(slot.runner, StatementExecutor):
        return slot.runner
    return c.bare_executor


def jog(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if not c.config.jog_supported:
        return Refused(err.JOG_REFUSED)
    try:
        request = Jog.parse("JOG" + arg)
    except RemoteProtocolError:
        return Refused(err.ILLEGAL_COMMAND)
    if c.origin_lost(now):
        return Refused(ORIGIN_NOT_SET)
    if c.alarm is not None:
        return Refused(ALARM_BLOCKS)
    if c.program_running:
        return Refused(err.BUSY)
    if not c.arm.servo:
        return Refused(err.SERVO_OFF)
    if request.negative == 0 and request.positive == 0:
        c.jogging = None
        c.arm.stop(now)
        return Ok()
    if c.jogging is None and c.arm.is_moving:
        return Refused(err.BUSY)
    try:
        c.arm.jog(request, now)
    except ArmFault as fault:
        return Refused(fault.number)
    c.jogging = JogState(request, now)
    return Ok()


def jogst(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [TRACE K9b-READ] RT ToolBox sends `1;0;JOGST` and gets `QoK`; meaning unknown.
    return Ok()


def stop(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [DOC S5] STOP needs no rights. Slot 0 stops all slots.
    c.jogging = None
    c.arm.stop(now)
    slots = c.slots.values() if req.slot in (0, 9) else [c.slot(req)]
    for slot in slots:
        c.pause_slot(slot, now)
    return Ok()


HANDLERS: dict[str, Handler] = {
    "SRVON": srvon,
    "SRVOFF": srvoff,
    "OVRD=": ovrd_set,
    "IN": in_,
    "OUT=": out_set,
    "OUT": out_get,
    "HNDON": hndon,
    "HNDOFF": hndoff,
    "HNDSTS": hndsts,
    "EXEC": exec_,
    "JOGST": jogst,
    "JOG": jog,
    "STOP": stop,
}
