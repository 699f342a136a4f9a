"""What the controller reports: STATE/DSTATE, positions, alarms and the error log, clock.

Answers are built with the same `melfa.protocol.answers` types the client reads them with.
"""

from __future__ import annotations

import datetime as dt

from melfa.protocol.answers import (
    JOINT_NAMES,
    POSE_NAMES,
    Position,
    RunStatus,
    Status,
    StopStatus,
)
from melfa.protocol.error_table import ErrorCode
from melfa.protocol.listings import ErrorLogEntry
from melfa.protocol.messages import Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.config import KeySwitch
from melfa.sim.core import ControllerCore, Handler, Slot, SlotState, error_message
from melfa.sim.runner import RunnerStatus

# ------------------------------------------------------------------------- alarms, log


def rstalrm(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.alarm = None
    return Ok()


def error(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.alarm is None:
        return Ok()
    return Ok(f"{c.alarm.number};{int(c.alarm.level)}")


def errorrd(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """The active errors, one entry per request [TRACE K9b-C1/C3/C4]: `ERRORRD<;0` the
    first, `ERRORRD+1;0` the next; an empty answer when there is none (more)."""
    where = arg.partition(";")[0].strip().upper()
    if where in ("<", "TOP", ""):
        c.log_cursor = 0
    elif where == "+1":
        c.log_cursor += 1
    else:
        return Refused(err.ILLEGAL_COMMAND)
    active = [] if c.alarm is None else [c.alarm]
    if c.log_cursor >= len(active):
        return Ok()
    entry = active[c.log_cursor]
    when = c.config.clock_origin + dt.timedelta(seconds=entry.at)
    return Ok(
        ErrorLogEntry(
            date=f"{when:%y-%m-%d}",
            time=f"{when:%H:%M:%S}",
            number=entry.number,
            text=entry.message,
            level=entry.level,
            program=entry.program,
            line=entry.line,
            code=ErrorCode(entry.number, f"{entry.detail:05d}"),
        ).to_answer()
    )


def errormes(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """The controller's text for an error number, 4 or 9 digits (`ERRORMES602000000` ->
    `The Operation is disable`) [TRACE K9b-PROG]."""
    try:
        code = ErrorCode.parse(arg.strip())
    except ValueError:
        return Refused(err.ILLEGAL_COMMAND)
    return Ok(error_message(code.number))


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
    """The `<RUN><STOP><ERRNO>` field of STATE and DSTATE for a slot [DOC S1 p.55], with the
    bits as real controllers set them [TRACE K9b]: idle `01120`/`21120` (repeat, stop,
    program selectable), running `60000`, paused mid-program `06` (stop + pause, no program
    selection: RUN<other> is refused 5120 "not PSA"), TEACH `0992…` (0x08 in the run byte,
    0x80 in the stop byte), an active alarm's number appended (`21125150`)."""
    run = RunStatus(0)
    if not (slot.cycle and slot.state is not SlotState.IDLE):
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
        stop = StopStatus.STOP | StopStatus.WAIT
    else:
        stop = StopStatus.STOP | StopStatus.PROGRAM_SELECT
    if c.key is KeySwitch.TEACH:
        run |= RunStatus.TEACH
        stop |= StopStatus.TEACH_PENDANT
    return Status(run, stop, c.alarm.number if c.alarm else 0)


_EDIT_STATUS = {SlotState.IDLE: "0", SlotState.PAUSED: "4", SlotState.RUNNING: "6"}
"""STATE's 4th field by slot state [TRACE K9b: 0 idle, 4 paused at line 1196, 6 running]."""


def state(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """Field for field as the K9b traces:
    idle `;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0`, running
    `SHOWOF.MB4;11;100;6;60000;11;1;;;;;;;;;REP;START;1;1`. `REP;START;1` is the slot's
    SLT parameter (repeat, start on START, priority 1), not how RUN was asked."""
    slot = c.slot(req)
    name = f"{slot.program}.MB4" if slot.program else ""
    line = slot.line
    if slot.runner is not None and slot.runner.status is RunnerStatus.FINISHED:
        # [TRACE K9b-PROG] after a cycle run ends: `QoK;0;100;0;21120;0;1;…`, no program
        # name and line 0 (a program selected but not yet run shows its name, line 1).
        name, line = "", 0
    fields = [
        name,
        str(line),
        str(c.arm.op_override),
        _EDIT_STATUS[slot.state],
        status(c, slot).to_field(),
        str(line),
        "1",
        *[""] * 8,
        "REP",
        "START",
        "1",
        "1" if slot.state is SlotState.RUNNING else "0",
    ]
    return Ok(";".join(fields))


def dstate(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    slot = c.slot(req)
    return Ok(f"{status(c, slot).to_field()};{slot.line};1")


def _round(value: float) -> float:
    # Print like the controller (2 decimals) without showing "-0.00".
    rounded = round(value, 2)
    return 0.0 if rounded == 0 else rounded


def _unknown(names: str | tuple[str, ...]) -> tuple[tuple[str, float | None], ...]:
    return tuple((name, None) for name in names)


def jposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if not c.origin_set:
        # [TRACE K9b-C4] `J1;****;…;;****,****;100;0.00;00000000`
        return Ok(Position(_unknown(JOINT_NAMES), None, None, c.arm.op_override, 0, 0).to_answer())
    axes = tuple(zip(JOINT_NAMES, (_round(v) for v in c.arm.joints), strict=True))
    answer = Position(axes, None, None, c.arm.op_override, c.arm.tcp_speed, 0)
    return Ok(answer.to_answer())


def pposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if not c.origin_set:
        return Ok(Position(_unknown(POSE_NAMES), None, None, c.arm.op_override, 0, 0).to_answer())
    pose = c.arm.pose
    values = (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)
    axes = tuple(zip(POSE_NAMES, (_round(v) for v in values), strict=True))
    answer = Position(axes, pose.fl1, pose.fl2, c.arm.op_override, c.arm.tcp_speed, 0)
    return Ok(answer.to_answer())


def gjposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """[TRACE K9b-PROG] all zero on a one-mechanism controller (the meaning of the G reads
    is not documented): `J1;0.00;…;;****,****;100;0.00;00000000`."""
    axes = tuple((name, 0.0) for name in JOINT_NAMES)
    return Ok(Position(axes, None, None, c.arm.op_override, 0, 0).to_answer())


def gpposf(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """[TRACE K9b-PROG] `X;0.00;…;;0,0;100;0.00;00000000`."""
    axes = tuple((name, 0.0) for name in POSE_NAMES)
    return Ok(Position(axes, 0, 0, c.arm.op_override, 0, 0).to_answer())


def time(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """The controller's clock, `yy-mm-ddhh:mm:ss` [TRACE K9b-C5: `22-10-3115:11:44`]."""
    when = c.config.clock_origin + dt.timedelta(seconds=now)
    return Ok(f"{when:%y-%m-%d%H:%M:%S}")


PTIME_FIELDS = 22
"""[TRACE K9b-C5] `404;118;118;0;…;19;0;2653;11947;1`: 22 fields, meanings undocumented."""


def ptime(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """Operating times [TRACE K9b-C5]: the simulator fills the first three (power-on,
    [GUESS] hours) and leaves the others 0, ending with `1` like the recording."""
    hours = str(int(now // 3600))
    return Ok(";".join([hours, hours, hours, *["0"] * (PTIME_FIELDS - 4), "1"]))


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


HANDLERS: dict[str, Handler] = {
    "RSTALRM": rstalrm,
    "ERRORMES": errormes,
    "ERRORLOG": errorlog,
    "ERRORRD": errorrd,
    "ERROR": error,
    "STATE": state,
    "DSTATE": dstate,
    "JPOSF": jposf,
    "PPOSF": pposf,
    "GJPOSF": gjposf,
    "GPPOSF": gpposf,
    "TIME": time,
    "PTIME": ptime,
    "CALIB": calib,
    "STPSIG": stpsig,
    "PRGRD": prgrd,
    "LINERD": linerd,
    "OVRD": ovrd_get,
}
