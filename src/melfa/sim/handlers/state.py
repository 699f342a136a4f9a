"""What the controller reports: STATE/DSTATE, positions, alarms and the error log.

Answers are built with the same `melfa.protocol.answers` types the client reads them with.
"""

from __future__ import annotations

import datetime as dt

from melfa.protocol.answers import Position, RunStatus, Status, StopStatus
from melfa.protocol.messages import Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.core import Command, ControllerCore, Slot, SlotState, error_message

# ------------------------------------------------------------------------- alarms, log


def rstalrm(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.alarm = None
    return Ok()


def error(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.alarm is None:
        return Ok()
    return Ok(f"{c.alarm.number};{int(c.alarm.level)}")


def errorrd(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [TRACE S21] `ERRORRD<;0` -> `QoK` with no error; [GUESS] like ERROR otherwise.
    return error(c, arg, req, now)


def errormes(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    digits = arg.strip()
    if not digits.isdigit():
        return Refused(err.ILLEGAL_COMMAND)
    return Ok(error_message(int(digits)))


def errorlog(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    where = arg.strip().upper()
    if where in ("TOP", "<"):
        c.log_cursor = 0
    elif where == "+1":
        c.log_cursor += 1
    elif where == "-1":
        c.log_cursor = max(0, c.log_cursor - 1)
    elif where == "END":
        c.log_cursor = max(0, len(c.error_log) - 1)
    else:
        return Refused(err.ILLEGAL_COMMAND)
    if not 0 <= c.log_cursor < len(c.error_log):
        return Ok()
    entry = c.error_log[c.log_cursor]
    when = c.config.clock_origin + dt.timedelta(seconds=entry.at)
    return Ok(
        f"{when:%y-%m-%d};{when:%H:%M:%S};{entry.number};{entry.message};"
        f"{int(entry.level)};{entry.program};{entry.line};"
    )


# ------------------------------------------------------------------------------ state


def status(c: ControllerCore, slot: Slot) -> Status:
    """The `<RUN><STOP><ERRNO>` field of STATE and DSTATE for a slot."""
    run = RunStatus(0)
    if not (slot.cycle and slot.state is not SlotState.IDLE):
        # [TRACE S21] idle slots show 0x01 (repeat); `RUN<name>;1` runs show cycle.
        run |= RunStatus.REPEAT
    if c.arm.servo:
        run |= RunStatus.SERVO_ON
    running = slot.state is SlotState.RUNNING or (
        c.config.run_bit_while_exec_moves and c.arm.is_moving
    )
    if running:
        run |= RunStatus.RUNNING
    if c.rights:
        run |= RunStatus.OPERATION_ENABLED
    if slot.state is SlotState.RUNNING:
        # [DOC S1 p.55] stop status 0x04 while the program sits in WAIT.
        stop = StopStatus.WAIT if slot.runner is not None and slot.runner.waiting else StopStatus(0)
    elif slot.state is SlotState.PAUSED:
        stop = StopStatus.STOP
    else:
        stop = StopStatus.STOP | StopStatus.PROGRAM_SELECT
    return Status(run, stop, c.alarm.number if c.alarm else 0)


def state(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # Layout as the S21 traces, field for field:
    #   idle:    `;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0`
    #   running: `SHOWOF.MB4;11;100;6;60000;11;1;;;;;;;;;REP;START;1;1`
    slot = c.slot(req)
    name = f"{slot.program}.MB4" if slot.program else ""
    running = slot.state is SlotState.RUNNING
    line = slot.line
    fields = [
        name,
        str(line),
        str(c.arm.op_override),
        "6" if running else "0",
        status(c, slot).to_field(),
        str(line),
        "1",
        *[""] * 8,
        "CYC" if slot.cycle and slot.state is not SlotState.IDLE else "REP",
        "START",
        "1",
        "1" if running else "0",
    ]
    return Ok(";".join(fields))


def dstate(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    slot = c.slot(req)
    return Ok(f"{status(c, slot).to_field()};{slot.line};1")


def _round(value: float) -> float:
    # Print like the controller (2 decimals) without showing "-0.00".
    rounded = round(value, 2)
    return 0.0 if rounded == 0 else rounded


def jposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    axes = tuple((f"J{i + 1}", _round(v)) for i, v in enumerate(c.arm.joints))
    answer = Position(axes, None, None, c.arm.op_override, c.arm.tcp_speed, 0)
    return Ok(answer.to_answer())


def pposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    pose = c.arm.pose
    values = (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)
    axes = tuple(zip("XYZABC", (_round(v) for v in values), strict=True))
    answer = Position(axes, pose.fl1, pose.fl2, c.arm.op_override, c.arm.tcp_speed, 0)
    return Ok(answer.to_answer())


def calib(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    return Ok("N3F3F")


def stpsig(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    return Ok("00;00")


def prgrd(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    slot = c.slot(req)
    return Ok(f"{slot.program}.MB4" if slot.program else "")


def linerd(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    return Ok(str(c.slot(req).line))


def ovrd_get(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if arg.strip():
        return Refused(err.ILLEGAL_COMMAND)
    return Ok(str(c.arm.op_override))


COMMANDS = (
    Command("RSTALRM", rstalrm, rights=True, exact=True),
    Command("ERRORMES", errormes),
    Command("ERRORLOG", errorlog),
    Command("ERRORRD", errorrd),
    Command("ERROR", error, exact=True),
    Command("STATE", state, exact=True),
    Command("DSTATE", dstate, exact=True),
    Command("JPOSF", jposf, exact=True),
    Command("PPOSF", pposf, exact=True),
    Command("CALIB", calib, exact=True),
    Command("STPSIG", stpsig, exact=True),
    Command("PRGRD", prgrd, exact=True),
    Command("LINERD", linerd, exact=True),
    Command("OVRD", ovrd_get),
)
