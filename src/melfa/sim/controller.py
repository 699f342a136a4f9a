"""The virtual CR2B-574: one request line in, one reply out, no I/O and no clock.

`VirtualController.handle(request, now)` answers exactly what protocol.md says the real
controller answers, with the same `melfa.protocol` code the client reads replies with, so
the two cannot drift. `now` (seconds, any origin, never decreasing) comes from the caller:
servers pass a monotonic clock, tests pass numbers. Motion happens on a `SimulatedArm`
advanced to `now` before each answer.

What it models: the OPEN session (6010 before OPEN), operation rights (6020), servo,
alarms (`Qok`/`Qer` while one is active, RSTALRM), the OP override, program memory with the
edit protocol (LOAD/EMDAT/SAVE/NEW…), task slots with RUN/STOP/RSTPRG through a
`ProgramRunner`, EXEC through a `StatementExecutor`, JOG with its ~140 ms watchdog, the
hand, STATE/DSTATE/JPOSF/PPOSF, the error log and the general-purpose I/O (one `IOState`
shared by the programs and EXEC; `set_input` drives inputs from outside, `IN`/`OUT` read
and write them over the protocol). What it does not: parameters beyond a few read-only
ones, VAL/HOT variables, file transfer (FOPEN…), breakpoints.

>>> c = VirtualController()
>>> c.handle(b"1;1;STATE\\r", now=0.0)
b'QeR6010\\r'
>>> c.handle(b"1;1;OPEN=NARCUSR\\r", now=0.0)[:12]
b'QoK3F;3F;7,0'
>>> c.handle(b"1;1;SRVON\\r", now=0.1)
b'QeR6020\\r'
"""

from __future__ import annotations

import datetime as dt
import enum
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from melfa.protocol.answers import ErrorLevel, Position, RunStatus, Status, StopStatus
from melfa.protocol.error_table import ERROR_MESSAGES
from melfa.protocol.errors import RemoteProtocolError
from melfa.protocol.jog import Jog
from melfa.protocol.messages import (
    VT,
    EditRefused,
    Ok,
    Refused,
    Reply,
    Request,
    encode_reply,
    parse_request,
)
from melfa.sim import errors as err
from melfa.sim.config import SimConfig
from melfa.sim.interp.io import IOState
from melfa.sim.machine import ArmFault, ControllerArm, SimArm, make_arm
from melfa.sim.runner import (
    LineWalker,
    ProgramRunner,
    RunnerFactory,
    RunnerStatus,
    StatementExecutor,
    StepError,
)
from melfa.sim.store import (
    EditBuffer,
    EditError,
    Program,
    ProgramStore,
    classify_item,
    program_name,
)
from melfa.sim.syntax import first_syntax_error

# Commands that need the operation rights [DOC S1/S2 §5.1, the `*` list], plus RSTALRM
# [DOC S5]. SRVOFF and STOP never need them [DOC S5].
_RIGHTS_DOC = frozenset(
    {"EXEC", "STEP", "PRGLOAD=", "LINENO=", "SRVON", "OVRD=", "RUN", "JOG", "RSTALRM"}
)
_SLOT_RESET = frozenset({"SLOTINIT", "RSTPRG"})

LISTL_MAX_ANSWER = 240
"""Largest LISTL answer body before "more follows" [GUESS: the real split point is unknown]."""

ALARM_BLOCKS = 5600
"""L5600 "Cannot execute during an error": motion commands while an alarm is active [DOC S4]."""

IO_WORD_BITS = 16
"""[GUESS] `IN<n>` / `OUT<n>` answer 16 signals from bit n as 4 hex digits, the width of
`OUT=<n>;<hex4>` [protocol.md §3.10 gives the commands, not the answers]."""


class SlotState(enum.Enum):
    IDLE = "idle"
    RUNNING = "running"
    PAUSED = "paused"


@dataclass
class Slot:
    """One task slot: the selected program and its runner."""

    number: int
    program: str | None = None
    runner: ProgramRunner | None = None
    cycle: bool = True

    @property
    def state(self) -> SlotState:
        if self.runner is None:
            return SlotState.IDLE
        status = self.runner.status
        if status is RunnerStatus.RUNNING:
            return SlotState.RUNNING
        if status is RunnerStatus.PAUSED:
            return SlotState.PAUSED
        return SlotState.IDLE

    @property
    def line(self) -> int:
        if self.runner is None or self.runner.line is None:
            return 1 if self.program else 0
        return self.runner.line


@dataclass(frozen=True, slots=True)
class Alarm:
    """An active controller error."""

    number: int
    level: ErrorLevel
    message: str
    at: float
    program: str = ""
    line: int = 0


@dataclass
class _JogState:
    jog: Jog
    last: float  # time of the last JOG request


_Handler = Callable[["VirtualController", str, Request, float], Reply]


@dataclass
class _Command:
    name: str
    handler: _Handler
    rights: bool = False
    needs_open: bool = True


def _level(number: int, letter: str | None = None) -> ErrorLevel:
    if letter is None:
        info = ERROR_MESSAGES.get(number)
        letter = info.level if info is not None else "L"
    return {"H": ErrorLevel.HIGH, "C": ErrorLevel.CAUTION}.get(letter, ErrorLevel.LOW)


def _message(number: int) -> str:
    info = ERROR_MESSAGES.get(number)
    return info.message if info is not None else f"Error {number}"


class VirtualController:
    """The sans-I/O core of the simulated CR2B-574.

    `runner_factory` makes the program runner of a slot (default: the interpreter when
    `melfa.sim.interp` offers one, else `LineWalker`); `executor` runs EXEC statements
    (default: the interpreter's, bound to this controller's arm). Both are hooks for tests.
    The default runners and EXEC share this controller's arm and its one `io`.
    """

    def __init__(
        self,
        config: SimConfig | None = None,
        *,
        arm: ControllerArm | None = None,
        runner_factory: RunnerFactory | None = None,
        executor: StatementExecutor | None = None,
        programs: Mapping[str, str] | None = None,
    ) -> None:
        self.config = config or SimConfig()
        self.arm: ControllerArm = arm if arm is not None else make_arm()
        self.io = IOState()
        """The controller's I/O signals: every program (RUN) and EXEC read and write these."""
        self._runner_factory = runner_factory or _default_runner_factory(self.arm, self.io)
        self._executor = executor
        self._bare_executor = _default_executor(self.arm, self.io) if executor is None else None
        self.store = ProgramStore()
        initial = {"COSIROP": ""} if programs is None else programs
        for name, text in initial.items():
            self.store.put(_program_from_text(name, text, self.config))
        self.slots = {n: Slot(n) for n in range(1, self.config.banner.taskmax + 1)}
        self.is_open = False
        self.client = ""
        self.rights = False
        self.alarm: Alarm | None = None
        self.error_log: list[Alarm] = []
        self._log_cursor = 0
        self.edit: EditBuffer | None = None
        self._listi_cursor = 0
        self._listp_cursor = 0
        self._jogging: _JogState | None = None
        self._now = 0.0

    # ------------------------------------------------------------------ clock and events

    def advance(self, now: float) -> None:
        """Bring the arm, the jog watchdog and the slots' programs up to `now`."""
        now = max(now, self._now)
        if self._jogging is not None:
            deadline = self._jogging.last + self.config.jog_watchdog_s
            if now >= deadline:
                # [DOC S1 §5.2.59] no JOG within ~140 ms: the jog stops by itself, at the
                # deadline, not whenever we happen to look.
                self._advance_arm(deadline)
                self.arm.stop(deadline)
                self._jogging = None
        for slot in self.slots.values():
            if slot.runner is not None and slot.runner.status is RunnerStatus.RUNNING:
                self._run_slot(slot, now)
        self._advance_arm(now)
        self._now = now

    def _run_slot(self, slot: Slot, now: float) -> None:
        runner = slot.runner
        if runner is None:
            return
        # The runner keeps its own timing between polls (a DLY or move that starts inside
        # `advance` starts when the previous step ended): one call is enough.
        runner.advance(now)
        failure = runner.error
        if failure is not None and _failed(runner) and self.alarm is None:
            self.raise_alarm(
                failure.number,
                now,
                program=slot.program or "",
                line=failure.line or 0,
                level=failure.level,
                message=failure.message,
            )

    def _advance_arm(self, now: float) -> None:
        try:
            self.arm.advance(now)
        except ArmFault as fault:
            self.raise_alarm(fault.number, now)

    @property
    def moving(self) -> bool:
        """The arm is moving (EXEC motion, jog or a program)."""
        return self.arm.is_moving

    @property
    def program_running(self) -> bool:
        return any(s.state is SlotState.RUNNING for s in self.slots.values())

    def raise_alarm(
        self,
        number: int,
        now: float,
        *,
        program: str = "",
        line: int = 0,
        level: str | None = None,
        message: str | None = None,
    ) -> None:
        """An error occurs: it becomes the active alarm and enters the error log. H-level
        errors switch the servo off; any error stops motion and pauses running programs.

        `level` (H/L/C) and `message` default to the error table's; a program error brings
        its own (user ERROR 9xxx numbers have no table entry)."""
        known = ERROR_MESSAGES.get(number)
        text = known.message if known is not None else (message or _message(number))
        alarm = Alarm(number, _level(number, level), text, now, program, line)
        self.alarm = alarm
        self.error_log.insert(0, alarm)
        self._jogging = None
        self.arm.stop(now)
        for slot in self.slots.values():
            if slot.runner is not None and slot.runner.status is RunnerStatus.RUNNING:
                slot.runner.pause(now)
        if alarm.level is ErrorLevel.HIGH:
            self.arm.set_servo(False, now)

    # -------------------------------------------------------------------------- requests

    def handle(self, request: bytes | str, now: float) -> bytes:
        """Answer one request line (with or without its CR) at time `now`."""
        return encode_reply(self.respond(request, now))

    def respond(self, request: bytes | str, now: float) -> Reply:
        """Like `handle`, as a typed reply."""
        self.advance(now)
        now = self._now
        data = request.encode("latin-1", "replace") if isinstance(request, str) else request
        try:
            parsed = parse_request(data)
        except RemoteProtocolError as exc:
            number = exc.error_number or err.ILLEGAL_COMMAND
            if number == err.COMMAND_TOO_LONG:
                number = self.config.too_long_error
            return self._refuse(number)
        text = parsed.command
        command = _lookup(text)
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

    def disconnect(self, now: float) -> None:
        """The line went away (a server's client closed): the session ends and a jog stops;
        programs, servo and alarms stay, as on the controller."""
        self.advance(now)
        if self._jogging is not None:
            self._jogging = None
            self.arm.stop(self._now)
        self.is_open = False
        self.rights = False

    # ------------------------------------------------------------------ session, rights

    def _open(self, arg: str, req: Request, now: float) -> Reply:
        # [DOC S1 §3.1] must come first; the name is arbitrary.
        self.is_open = True
        self.client = arg
        return Ok(self.config.banner.body())

    def _close(self, arg: str, req: Request, now: float) -> Reply:
        self.is_open = False
        self.rights = False
        return Ok()

    def _cntlon(self, arg: str, req: Request, now: float) -> Reply:
        self.rights = True
        return Ok()

    def _cntloff(self, arg: str, req: Request, now: float) -> Reply:
        self.rights = False
        return Ok()

    def _ok(self, arg: str, req: Request, now: float) -> Reply:
        return Ok()

    def _prtver(self, arg: str, req: Request, now: float) -> Reply:
        # [TRACE S21] PRTVERVALS -> QoK1; [GUESS] the same for LISTL/EMDAT.
        return Ok(self.config.prtver_answer)

    def _par(self, arg: str, req: Request, now: float) -> Reply:
        name = arg.strip().upper()
        value = _parameters(self).get(name)
        if value is None:
            return Refused(err.PARAMETER_NOT_FOUND)
        values, count = value
        return Ok(f"{name};{values};{count}")

    # -------------------------------------------------------------------- servo, alarms

    def _srvon(self, arg: str, req: Request, now: float) -> Reply:
        if self.alarm is not None:
            return Refused(err.SERVO_ON_DURING_ERROR)
        self.arm.set_servo(True, now)
        return Ok()

    def _srvoff(self, arg: str, req: Request, now: float) -> Reply:
        self._jogging = None
        self.arm.stop(now)
        self.arm.set_servo(False, now)
        return Ok()

    def _rstalrm(self, arg: str, req: Request, now: float) -> Reply:
        self.alarm = None
        return Ok()

    def _error(self, arg: str, req: Request, now: float) -> Reply:
        if self.alarm is None:
            return Ok()
        return Ok(f"{self.alarm.number};{int(self.alarm.level)}")

    def _errorrd(self, arg: str, req: Request, now: float) -> Reply:
        # [TRACE S21] `ERRORRD<;0` -> `QoK` with no error; [GUESS] like ERROR otherwise.
        return self._error(arg, req, now)

    def _errormes(self, arg: str, req: Request, now: float) -> Reply:
        digits = arg.strip()
        if not digits.isdigit():
            return Refused(err.ILLEGAL_COMMAND)
        return Ok(_message(int(digits)))

    def _errorlog(self, arg: str, req: Request, now: float) -> Reply:
        where = arg.strip().upper()
        if where in ("TOP", "<"):
            self._log_cursor = 0
        elif where == "+1":
            self._log_cursor += 1
        elif where == "-1":
            self._log_cursor = max(0, self._log_cursor - 1)
        elif where == "END":
            self._log_cursor = max(0, len(self.error_log) - 1)
        else:
            return Refused(err.ILLEGAL_COMMAND)
        if not 0 <= self._log_cursor < len(self.error_log):
            return Ok()
        entry = self.error_log[self._log_cursor]
        when = self.config.clock_origin + _seconds(entry.at)
        return Ok(
            f"{when:%y-%m-%d};{when:%H:%M:%S};{entry.number};{entry.message};"
            f"{int(entry.level)};{entry.program};{entry.line};"
        )

    # -------------------------------------------------------------------------- state

    def _status(self, slot: Slot) -> Status:
        run = RunStatus(0)
        if not (slot.cycle and slot.state is not SlotState.IDLE):
            # [TRACE S21] idle slots show 0x01 (repeat); `RUN<name>;1` runs show cycle.
            run |= RunStatus.REPEAT
        if self.arm.servo:
            run |= RunStatus.SERVO_ON
        running = slot.state is SlotState.RUNNING or (
            self.config.run_bit_while_exec_moves and self.arm.is_moving
        )
        if running:
            run |= RunStatus.RUNNING
        if self.rights:
            run |= RunStatus.OPERATION_ENABLED
        if slot.state is SlotState.RUNNING:
            # [DOC S1 p.55] stop status 0x04 while the program sits in WAIT.
            stop = (
                StopStatus.WAIT
                if slot.runner is not None and slot.runner.waiting
                else StopStatus(0)
            )
        elif slot.state is SlotState.PAUSED:
            stop = StopStatus.STOP
        else:
            stop = StopStatus.STOP | StopStatus.PROGRAM_SELECT
        return Status(run, stop, self.alarm.number if self.alarm else 0)

    def _slot(self, req: Request) -> Slot:
        return self.slots.get(req.slot) or self.slots[1]

    def _state(self, arg: str, req: Request, now: float) -> Reply:
        # Layout as the S21 traces, field for field:
        #   idle:    `;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0`
        #   running: `SHOWOF.MB4;11;100;6;60000;11;1;;;;;;;;;REP;START;1;1`
        slot = self._slot(req)
        name = f"{slot.program}.MB4" if slot.program else ""
        running = slot.state is SlotState.RUNNING
        line = slot.line
        fields = [
            name,
            str(line),
            str(self.arm.op_override),
            "6" if running else "0",
            self._status(slot).to_field(),
            str(line),
            "1",
            *[""] * 8,
            "CYC" if slot.cycle and slot.state is not SlotState.IDLE else "REP",
            "START",
            "1",
            "1" if running else "0",
        ]
        return Ok(";".join(fields))

    def _dstate(self, arg: str, req: Request, now: float) -> Reply:
        slot = self._slot(req)
        return Ok(f"{self._status(slot).to_field()};{slot.line};1")

    def _jposf(self, arg: str, req: Request, now: float) -> Reply:
        joints = self.arm.joints
        axes = tuple((f"J{i + 1}", _round(v)) for i, v in enumerate(joints))
        answer = Position(axes, None, None, self.arm.op_override, self.arm.tcp_speed, 0)
        return Ok(answer.to_answer())

    def _pposf(self, arg: str, req: Request, now: float) -> Reply:
        pose = self.arm.pose
        values = (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)
        axes = tuple(zip("XYZABC", (_round(v) for v in values), strict=True))
        answer = Position(axes, pose.fl1, pose.fl2, self.arm.op_override, self.arm.tcp_speed, 0)
        return Ok(answer.to_answer())

    def _calib(self, arg: str, req: Request, now: float) -> Reply:
        return Ok("N3F3F")

    def _stpsig(self, arg: str, req: Request, now: float) -> Reply:
        return Ok("00;00")

    def _prgrd(self, arg: str, req: Request, now: float) -> Reply:
        slot = self._slot(req)
        return Ok(f"{slot.program}.MB4" if slot.program else "")

    def _linerd(self, arg: str, req: Request, now: float) -> Reply:
        return Ok(str(self._slot(req).line))

    # ---------------------------------------------------------------------------- I/O

    def set_input(self, bit: int, value: int | bool) -> None:
        """Drive input signal `bit` (a sensor, the operator, a test, the UI). A program in
        WAIT sees it at its next `advance`."""
        self.io.set_input(bit, value)

    def _signal_bit(self, text: str) -> int | None:
        value = text.strip()
        return int(value) if value.isdigit() else None

    def _in(self, arg: str, req: Request, now: float) -> Reply:
        bit = self._signal_bit(arg)
        if bit is None:
            return Refused(err.ILLEGAL_COMMAND)
        return Ok(f"{self.io.read_inputs(bit, IO_WORD_BITS):04X}")

    def _out_get(self, arg: str, req: Request, now: float) -> Reply:
        bit = self._signal_bit(arg)
        if bit is None:
            return Refused(err.ILLEGAL_COMMAND)
        return Ok(f"{self.io.read_outputs(bit, IO_WORD_BITS):04X}")

    def _out_set(self, arg: str, req: Request, now: float) -> Reply:
        # `OUT=<n>;<hex4>` [protocol.md §3.10]: 16 output signals from n.
        start, _, value = arg.partition(";")
        bit = self._signal_bit(start)
        try:
            word = int(value.strip(), 16)
        except ValueError:
            return Refused(err.ILLEGAL_COMMAND)
        if bit is None or not 0 <= word <= 0xFFFF:
            return Refused(err.ILLEGAL_COMMAND)
        self.io.write_outputs(bit, IO_WORD_BITS, word)
        return Ok()

    # ---------------------------------------------------------------------- override

    def _ovrd_set(self, arg: str, req: Request, now: float) -> Reply:
        value = arg.strip()
        if not value.isdigit() or not 1 <= int(value) <= 100:
            return Refused(err.ARGUMENT_OUT_OF_RANGE)
        self.arm.set_op_override(int(value), now)
        return Ok(str(int(value)))

    def _ovrd_get(self, arg: str, req: Request, now: float) -> Reply:
        if arg.strip():
            return Refused(err.ILLEGAL_COMMAND)
        return Ok(str(self.arm.op_override))

    # -------------------------------------------------------------------------- hand

    def _hand(self, arg: str, on: bool, now: float) -> Reply:
        value = arg.strip()
        if not value.isdigit() or not 1 <= int(value) <= 8:
            return Refused(err.ARGUMENT_OUT_OF_RANGE)
        opened = on == self.config.hand_on_opens
        self.arm.set_hand(int(value), opened, now)
        return Ok()

    def _hndon(self, arg: str, req: Request, now: float) -> Reply:
        return self._hand(arg, True, now)

    def _hndoff(self, arg: str, req: Request, now: float) -> Reply:
        return self._hand(arg, False, now)

    def _hndsts(self, arg: str, req: Request, now: float) -> Reply:
        # [DOC S1 §5.2.56] 8 x `<signal no>;<1 open, 2 closed>;<0 single / 1 double>`,
        # e.g. `900;2;1;902;1;1;…`: hand n uses output signals 900 + 2(n-1).
        parts = []
        for hand in range(1, 9):
            parts += [str(900 + 2 * (hand - 1)), "1" if self.arm.hand_open(hand) else "2", "1"]
        return Ok(";".join(parts))

    # ------------------------------------------------------------------------- motion

    def _exec(self, arg: str, req: Request, now: float) -> Reply:
        statement = arg.strip()
        if self.alarm is not None:
            return Refused(ALARM_BLOCKS)
        # [CODE S6/S7] any EXEC while the arm still moves is refused with 5640; S6 uses
        # `EXECREM Waiting...` as its busy test.
        if self.moving or self.program_running:
            return Refused(err.BUSY)
        slot = self._slot(req)
        if self.config.exec_needs_program and slot.program is None and req.slot != 9:
            return Refused(err.PROGRAM_NOT_FOUND)
        executor = self._executor_for(slot)
        if executor is None:
            return Refused(err.ILLEGAL_COMMAND)
        self._jogging = None
        executor.execute(statement, now)
        return Ok()

    def _executor_for(self, slot: Slot) -> StatementExecutor | None:
        """EXEC runs in the slot's program (its variables) when one is loaded [DOC S1
        §5.2.16: "in the task slot"], else in a bare interpreter; `executor=` overrides."""
        if self._executor is not None:
            return self._executor
        if isinstance(slot.runner, StatementExecutor):
            return slot.runner
        return self._bare_executor

    def _jog(self, arg: str, req: Request, now: float) -> Reply:
        if not self.config.jog_supported:
            return Refused(err.JOG_REFUSED)
        try:
            jog = Jog.parse("JOG" + arg)
        except RemoteProtocolError:
            return Refused(err.ILLEGAL_COMMAND)
        if self.alarm is not None:
            return Refused(ALARM_BLOCKS)
        if self.program_running:
            return Refused(err.BUSY)
        if not self.arm.servo:
            return Refused(err.SERVO_OFF)
        if jog.negative == 0 and jog.positive == 0:
            self._jogging = None
            self.arm.stop(now)
            return Ok()
        if self._jogging is None and self.arm.is_moving:
            return Refused(err.BUSY)
        try:
            self.arm.jog(jog, now)
        except ArmFault as fault:
            return Refused(fault.number)
        self._jogging = _JogState(jog, now)
        return Ok()

    def _jogst(self, arg: str, req: Request, now: float) -> Reply:
        # [TRACE S21] RT ToolBox sends `1;0;JOGST` and gets `QoK`; meaning unknown.
        return Ok()

    def _stop(self, arg: str, req: Request, now: float) -> Reply:
        # [DOC S5] STOP needs no rights. Slot 0 stops all slots.
        self._jogging = None
        self.arm.stop(now)
        slots = self.slots.values() if req.slot in (0, 9) else [self._slot(req)]
        for slot in slots:
            if slot.runner is not None and slot.runner.status is RunnerStatus.RUNNING:
                slot.runner.pause(now)
        return Ok()

    # ------------------------------------------------------------------------ programs

    def _prgload(self, arg: str, req: Request, now: float) -> Reply:
        name = program_name(arg)
        slot = self._slot(req)
        if slot.state is not SlotState.IDLE:
            # [DOC S1 §4.6] refused while a program runs or is paused: SLOTINIT first.
            return Refused(err.PROGRAM_RUNNING)
        if name is None or name not in self.store:
            return Refused(err.PROGRAM_NOT_FOUND)
        self._select(slot, name)
        return Ok()

    def _select(self, slot: Slot, name: str) -> None:
        program = self.store.get(name)
        assert program is not None
        runner = self._runner_factory()
        runner.load(program.text(), program.positions)
        slot.program = name
        slot.runner = runner

    def _run(self, arg: str, req: Request, now: float) -> Reply:
        slot = self._slot(req)
        name_part, _, mode = arg.partition(";")
        cycle = mode.strip() != "0"
        if slot.state is SlotState.RUNNING:
            return Refused(err.PROGRAM_RUNNING)
        if self.alarm is not None:
            return Refused(ALARM_BLOCKS)
        if self.moving:
            return Refused(err.BUSY)
        if name_part.strip():
            name = program_name(name_part)
            if name is None or name not in self.store:
                return Refused(err.PROGRAM_NOT_FOUND)
            if self.edit is not None and self.edit.name == name:
                return Refused(err.PROGRAM_BEING_EDITED)
            if slot.state is SlotState.PAUSED and slot.program == name:
                slot.cycle = cycle
                assert slot.runner is not None
                slot.runner.resume(now)
                self._started(slot, now)
                return Ok()
            if slot.state is SlotState.PAUSED:
                return Refused(err.PROGRAM_RUNNING)
            self._select(slot, name)
        elif slot.program is None or slot.runner is None:
            return Refused(err.PROGRAM_NOT_FOUND)
        elif slot.state is SlotState.PAUSED:
            slot.runner.resume(now)
            self._started(slot, now)
            return Ok()
        assert slot.runner is not None
        slot.cycle = cycle
        slot.runner.start(now, cycle=cycle)
        self._started(slot, now)
        return Ok()

    def _started(self, slot: Slot, now: float) -> None:
        """A program starts executing at the RUN, not at the next request."""
        self._run_slot(slot, now)

    def _rstprg(self, arg: str, req: Request, now: float) -> Reply:
        slot = self._slot(req)
        if slot.state is SlotState.RUNNING:
            return Refused(err.PROGRAM_RUNNING)
        if slot.runner is not None:
            slot.runner.reset()
        return Ok()

    def _slotinit(self, arg: str, req: Request, now: float) -> Reply:
        if self.program_running:
            return Refused(err.PROGRAM_RUNNING)
        for slot in self.slots.values():
            if slot.runner is not None:
                slot.runner.reset()
        return Ok()

    # ------------------------------------------------------------------------- editing

    def _load(self, arg: str, req: Request, now: float) -> Reply:
        name = program_name(arg)
        if name is None:
            return Refused(err.BAD_PROGRAM_NAME)
        if any(s.program == name and s.state is not SlotState.IDLE for s in self.slots.values()):
            return Refused(err.PROGRAM_RUNNING)
        self.edit = EditBuffer.of(name, self.store.get(name))
        self._listi_cursor = 0
        self._listp_cursor = 0
        return Ok()

    def _new(self, arg: str, req: Request, now: float) -> Reply:
        self.edit = None
        return Ok()

    def _eclr(self, arg: str, req: Request, now: float) -> Reply:
        if self.edit is not None:
            self.edit.clear()
        return Ok()

    def _emdat(self, arg: str, req: Request, now: float) -> Reply:
        if self.edit is None:
            return Refused(err.NOT_EDITING)
        # [DOC S1 p.8] items are separated by VT; a trailing VT leaves an empty item.
        items = arg.split(VT)
        staged = EditBuffer(self.edit.name, dict(self.edit.lines), dict(self.edit.positions))
        for index, raw in enumerate(items, start=1):
            if not raw.strip():
                continue
            try:
                item = classify_item(raw)
                if self.config.check_syntax_on_emdat and item.text is not None:
                    self._check_step(item.text, raw)
            except EditError as bad:
                return EditRefused(bad.number, index, bad.column)
            staged.apply(item)
        # A refused batch changes nothing [GUESS: all-or-nothing per EMDAT].
        self.edit = staged
        return Ok()

    def _edata(self, arg: str, req: Request, now: float) -> Reply:
        if self.edit is None:
            return Refused(err.NOT_EDITING)
        try:
            item = classify_item(arg)
            if self.config.check_syntax_on_emdat and item.text is not None:
                self._check_step(item.text, arg)
        except EditError as bad:
            return EditRefused(bad.number, None, bad.column)
        self.edit.apply(item)
        return Ok()

    def _check_step(self, text: str, raw: str) -> None:
        found = first_syntax_error(text)
        if found is not None:
            number, column = found
            offset = len(raw) - len(raw.lstrip(" "))
            raise EditError(number, offset + column, f"syntax error in {text!r}")

    def _save(self, arg: str, req: Request, now: float) -> Reply:
        if self.edit is None:
            # [TRACE §4.2 item 6] the thesis sends SAVE with nothing open before deleting.
            return Ok()
        found = first_syntax_error(self.edit.text())
        if found is not None:
            # The old program stays; the edit slot stays open for corrections.
            return Refused(found[0])
        when = self.config.clock_origin + _seconds(now)
        self.store.put(self.edit.to_program(when))
        name = self.edit.name
        self.edit = None
        for slot in self.slots.values():
            if slot.program == name and slot.state is SlotState.IDLE:
                self._select(slot, name)
        return Ok()

    def _listing_program(self, req: Request) -> EditBuffer | None:
        if self.edit is not None:
            return self.edit
        program = self.store.get(self._slot(req).program or "")
        return EditBuffer.of(program.name, program) if program is not None else None

    def _listl(self, arg: str, req: Request, now: float) -> Reply:
        # `LISTL<pos>`: `QoK<line>[VT<line>…];<count>;<1 more follows / 0 end>`.
        buffer = self._listing_program(req)
        lines = [] if buffer is None else [buffer.lines[n] for n in sorted(buffer.lines)]
        start = arg.strip().lstrip("<").upper()
        if start and start != "TOP":
            if not start.isdigit():
                return Refused(err.ILLEGAL_COMMAND)
            lines = [ln for ln in lines if int(ln.split(" ", 1)[0]) >= int(start)]
        chosen: list[str] = []
        size = 0
        for line in lines:
            if chosen and size + len(line) + 1 > LISTL_MAX_ANSWER:
                break
            chosen.append(line)
            size += len(line) + 1
        more = "1" if len(chosen) < len(lines) else "0"
        return Ok(f"{VT.join(chosen)};{len(chosen)};{more}")

    def _listi(self, arg: str, req: Request, now: float) -> Reply:
        buffer = self._listing_program(req)
        numbers = [] if buffer is None else sorted(buffer.lines)
        where = arg.strip().upper()
        if where == "TOP":
            self._listi_cursor = 0
        elif where == "+1":
            self._listi_cursor += 1
        elif where == "-1":
            self._listi_cursor = max(0, self._listi_cursor - 1)
        elif where.isdigit():
            wanted = int(where)
            self._listi_cursor = next(
                (i for i, n in enumerate(numbers) if n >= wanted), len(numbers)
            )
        else:
            return Refused(err.ILLEGAL_COMMAND)
        if buffer is None or not 0 <= self._listi_cursor < len(numbers):
            return Ok()
        return Ok(buffer.lines[numbers[self._listi_cursor]])

    def _listp(self, arg: str, req: Request, now: float) -> Reply:
        buffer = self._listing_program(req)
        names = [] if buffer is None else list(buffer.positions)
        where = arg.strip().upper()
        if where == "TOP":
            self._listp_cursor = 0
        elif where == "+1":
            self._listp_cursor += 1
        elif where in names:
            self._listp_cursor = names.index(where)
        else:
            return Refused(err.VARIABLE_NOT_DEFINED)
        if buffer is None or not 0 <= self._listp_cursor < len(names):
            return Ok()
        return Ok(_format_position(buffer.positions[names[self._listp_cursor]]))

    def _pdir(self, arg: str, req: Request, now: float) -> Reply:
        # [TRACE S21] `PDIR<` (and TOP): first entry with count and free bytes;
        # `PDIRnn`: entry nn (1-based) without them; empty: `QoK;;;0;225536;;;;;;;`.
        where = arg.strip().upper()
        names = self.store.names()
        free = max(0, self.config.free_bytes - self.store.total_size())
        if where in ("<", "TOP", ""):
            if not names:
                return Ok(f";;;0;{free};;;;;;;")
            return Ok(self._pdir_entry(names[0], f"{len(names)};{free};"))
        if not where.isdigit():
            return Refused(err.ILLEGAL_COMMAND)
        index = int(where)
        if not 1 <= index <= len(names):
            return Ok()
        return Ok(self._pdir_entry(names[index - 1], ""))

    def _pdir_entry(self, name: str, middle: str) -> str:
        program = self.store.get(name)
        assert program is not None
        stamp = f"{program.saved_at:%y-%m-%d%H:%M:%S}"
        return (
            f"{program.file_name};{program.size()};{stamp};{middle}12;;"
            f"{len(program.lines)};{len(program.positions)};0;0;0;0"
        )

    def _fdel(self, arg: str, req: Request, now: float) -> Reply:
        name = program_name(arg)
        if name is None or name not in self.store:
            return Refused(err.PROGRAM_NOT_FOUND)
        if any(s.program == name and s.state is not SlotState.IDLE for s in self.slots.values()):
            return Refused(err.PROGRAM_RUNNING)
        self.store.delete(name)
        for slot in self.slots.values():
            if slot.program == name:
                slot.program = None
                slot.runner = None
        return Ok()

    def _fcheck(self, arg: str, req: Request, now: float) -> Reply:
        # [DOC S1] `QoKN` = exists, `QoKF` = missing.
        name = program_name(arg)
        return Ok("N" if name is not None and name in self.store else "F")


# ------------------------------------------------------------------------------ helpers


def _failed(runner: ProgramRunner) -> bool:
    return runner.status is RunnerStatus.FAILED


def _seconds(now: float) -> dt.timedelta:
    return dt.timedelta(seconds=now)


def _round(value: float) -> float:
    # Print like the controller (2 decimals) without showing "-0.00".
    rounded = round(value, 2)
    return 0.0 if rounded == 0 else rounded


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)")


def _format_position(definition: str) -> str:
    """`P1=(400.13,0,644.62,180,0,180)(7,0)` -> `P1=(+400.13,+0.00,…)(7,0)` as LISTP shows it
    [DOC S1 example]; a value that is not a number is kept as written."""
    name, _, rest = definition.partition("=")
    values, _, flags = rest.strip().lstrip("(").partition(")")

    def one(text: str) -> str:
        text = text.strip()
        if not _NUMBER.fullmatch(text):
            return text
        return f"{float(text):+.2f}"

    body = ",".join(one(v) for v in values.split(","))
    return f"{name.strip().upper()}=({body}){flags.strip()}"


def _parameters(controller: VirtualController) -> dict[str, tuple[str, int]]:
    """Read-only parameters PAR<name> answers [TRACE S10; DERIVED for MEJAR]."""
    limits = controller.arm.joint_limits
    mejar = [f"{v:.2f}" for pair in limits for v in pair]
    mejar += ["0.00"] * (16 - len(mejar))
    return {
        "RLNG": ("1", 1),
        "MEXTL": (", ".join(f"{v:.2f}" for v in controller.arm.tool_values), 6),
        "MEJAR": (", ".join(mejar), 16),
        "CBAU232": ("9600", 1),
        "CPRTY232": ("2", 1),
        "CSTOP232": ("2", 1),
        "CTERM232": ("0", 1),
        "CPRC232": ("0", 1),
        "TASKMAX": (str(controller.config.banner.taskmax), 1),
    }


def _program_from_text(name: str, text: str, config: SimConfig) -> Program:
    lines: dict[int, str] = {}
    positions: dict[str, str] = {}
    for raw in text.splitlines():
        if not raw.strip():
            continue
        item = classify_item(raw)
        if item.text is not None and item.line is not None:
            lines[item.line] = item.text
        elif item.position is not None and item.definition is not None:
            positions[item.position] = item.definition
    clean = program_name(name)
    if clean is None:
        raise ValueError(f"bad program name {name!r}")
    return Program(clean, lines, positions, config.clock_origin)


def _default_runner_factory(arm: ControllerArm, io: IOState) -> RunnerFactory:
    """The interpreter on the shared `SimulatedArm` and I/O; `LineWalker` for a foreign arm."""
    if not isinstance(arm, SimArm):
        return LineWalker
    from melfa.sim.interp.armport import ArmPort
    from melfa.sim.interp.interpreter import Interpreter

    port = ArmPort(arm.arm)
    return lambda: Interpreter(port, io)


def _default_executor(arm: ControllerArm, io: IOState) -> StatementExecutor | None:
    """EXEC outside any loaded program: a bare interpreter on the shared arm and I/O."""
    if not isinstance(arm, SimArm):
        return None
    from melfa.sim.interp.armport import ArmPort
    from melfa.sim.interp.interpreter import Interpreter

    return Interpreter(ArmPort(arm.arm), io)


VC = VirtualController
_TABLE: list[_Command] = [
    _Command("OPEN=", VC._open, needs_open=False),
    _Command("CLOSE", VC._close),
    _Command("CNTLON", VC._cntlon),
    _Command("CNTLOFF", VC._cntloff),
    _Command("KEYWD", VC._ok),
    _Command("PRTVER", VC._prtver),
    _Command("PAR", VC._par),
    _Command("SRVON", VC._srvon, rights=True),
    _Command("SRVOFF", VC._srvoff),
    _Command("RSTALRM", VC._rstalrm, rights=True),
    _Command("ERRORMES", VC._errormes),
    _Command("ERRORLOG", VC._errorlog),
    _Command("ERRORRD", VC._errorrd),
    _Command("ERROR", VC._error),
    _Command("STATE", VC._state),
    _Command("DSTATE", VC._dstate),
    _Command("JPOSF", VC._jposf),
    _Command("PPOSF", VC._pposf),
    _Command("CALIB", VC._calib),
    _Command("STPSIG", VC._stpsig),
    _Command("PRGRD", VC._prgrd),
    _Command("LINERD", VC._linerd),
    _Command("OVRD=", VC._ovrd_set, rights=True),
    _Command("OVRD", VC._ovrd_get),
    _Command("IN", VC._in),
    _Command("OUT=", VC._out_set),
    _Command("OUT", VC._out_get),
    _Command("HNDON", VC._hndon),
    _Command("HNDOFF", VC._hndoff),
    _Command("HNDSTS", VC._hndsts),
    _Command("EXEC", VC._exec, rights=True),
    _Command("JOGST", VC._jogst),
    _Command("JOG", VC._jog, rights=True),
    _Command("STOP", VC._stop),
    _Command("PRGLOAD=", VC._prgload, rights=True),
    _Command("RUN", VC._run, rights=True),
    _Command("RSTPRG", VC._rstprg),
    _Command("SLOTINIT", VC._slotinit),
    _Command("LOAD=", VC._load),
    _Command("NEW", VC._new),
    _Command("ECLR", VC._eclr),
    _Command("EMDAT", VC._emdat),
    _Command("EDATA", VC._edata),
    _Command("SAVE", VC._save),
    _Command("LISTL", VC._listl),
    _Command("LISTI", VC._listi),
    _Command("LISTP", VC._listp),
    _Command("PDIR", VC._pdir),
    _Command("FDEL", VC._fdel),
    _Command("FCHECK", VC._fcheck),
]
assert all(c.rights == (c.name in _RIGHTS_DOC) for c in _TABLE), "rights table drifted"
_BY_LENGTH = sorted(_TABLE, key=lambda c: len(c.name), reverse=True)
_EXACT = frozenset(
    {
        "CLOSE",
        "CNTLON",
        "CNTLOFF",
        "SRVON",
        "SRVOFF",
        "RSTALRM",
        "ERROR",
        "STATE",
        "DSTATE",
        "JPOSF",
        "PPOSF",
        "CALIB",
        "STPSIG",
        "PRGRD",
        "LINERD",
        "HNDSTS",
        "JOGST",
        "STOP",
        "RSTPRG",
        "SLOTINIT",
        "NEW",
        "ECLR",
        "SAVE",
    }
)
SUPPORTED_COMMANDS: tuple[str, ...] = tuple(c.name for c in _TABLE)
"""Every command word the virtual controller answers (prefixes for those with arguments)."""


def _lookup(text: str) -> _Command | None:
    upper = text.upper()
    for command in _BY_LENGTH:
        if upper.startswith(command.name):
            rest = upper[len(command.name) :]
            if command.name in _EXACT and rest.strip():
                continue
            return command
    return None
