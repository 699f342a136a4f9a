"""The virtual controller's state and clock: what every request handler reads and changes.

`ControllerCore` holds the session, the rights, the task slots, the program memory with its
edit slot, the active alarm and the error log, the jog watchdog and the simulated arm, and
brings them up to an injected time (`advance(now)`). It answers nothing: the handlers in
`melfa.sim.handlers` do, one module per job, and `melfa.sim.controller.VirtualController`
dispatches requests to them. No I/O and no clock inside.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from melfa.protocol.error_table import ERROR_MESSAGES, ORIGIN_NOT_SET, ErrorLevel, error_level
from melfa.protocol.jog import Jog
from melfa.protocol.messages import Reply, Request
from melfa.sim.config import KeySwitch, SimConfig
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.io import IOState
from melfa.sim.machine import ArmFault, ControllerArm, SimArm, make_arm
from melfa.sim.runner import (
    LineWalker,
    ProgramRunner,
    RunnerFactory,
    RunnerStatus,
    StatementExecutor,
)
from melfa.sim.store import EditBuffer, Program, ProgramStore, classify_item, program_name

ORIGIN_LOG_DETAIL = 100
"""The detail digits of L5150 in the error log: `515000100` [TRACE K9b-C1]."""


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
    held_speeds: object | None = None
    """The speed settings of a paused program, put aside until it resumes."""

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
    """An active controller error (and one entry of the error log).

    `detail` is the 5 digits a 9-digit refusal and the log carry after the number
    (`515000100`: error 5150, detail `00100`) [TRACE K9b-C1]."""

    number: int
    level: ErrorLevel
    message: str
    at: float
    program: str = ""
    line: int = 0
    detail: int = 0


@dataclass
class JogState:
    jog: Jog
    last: float  # time of the last JOG request


def error_message(number: int) -> str:
    """The controller's text for an error number (`ERRORMES`), or a plain fallback."""
    info = ERROR_MESSAGES.get(number)
    return info.message if info is not None else f"Error {number}"


class ControllerCore:
    """State of the simulated CR2B-574, advanced by an injected clock.

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
        self.arm: ControllerArm = arm if arm is not None else make_arm(self.config.jog_watchdog_s)
        self.io = IOState()
        """The controller's I/O signals: every program (RUN) and EXEC read and write these."""
        self.runner_factory = runner_factory or _default_runner_factory(self.arm, self.io)
        self.executor = executor
        self.bare_executor = _default_executor(self.arm, self.io) if executor is None else None
        self.store = ProgramStore()
        initial = {"COSIROP": ""} if programs is None else programs
        for name, text in initial.items():
            self.store.put(program_from_text(name, text, self.config))
        self.slots = {n: Slot(n) for n in range(1, self.config.banner.taskmax + 1)}
        self.is_open = False
        self.client = ""
        self.rights = False
        self.alarm: Alarm | None = None
        self.error_log: list[Alarm] = []
        self.log_cursor = 0
        self.edit: EditBuffer | None = None
        self.listi_cursor = 0
        self.listp_cursor = 0
        self.jogging: JogState | None = None
        self.now = 0.0
        self.key = self.config.key
        """Where the MODE key stands (`turn_key`)."""
        self.origin_set = self.config.origin_set
        """False: encoder data lost; positions read `****`, motion raises L5150."""

    # ------------------------------------------------------------------ clock and events

    def advance(self, now: float) -> None:
        """Bring the arm, the jog watchdog and the slots' programs up to `now`."""
        now = max(now, self.now)
        if self.jogging is not None:
            deadline = self.jogging.last + self.config.jog_watchdog_s
            if now >= deadline:
                # [DOC S1 §5.2.59] no JOG within ~140 ms: the jog stops by itself, at the
                # deadline, not whenever we happen to look.
                self.advance_arm(deadline)
                self.arm.stop(deadline)
                self.jogging = None
        for slot in self.slots.values():
            if slot.runner is not None and slot.runner.status is RunnerStatus.RUNNING:
                self.run_slot(slot, now)
        self.advance_arm(now)
        self.now = now

    def run_slot(self, slot: Slot, now: float) -> None:
        """Run a slot's program up to `now`; a run-time error becomes the alarm."""
        runner = slot.runner
        if runner is None:
            return
        # The runner keeps its own timing between polls (a DLY or move that starts inside
        # `advance` starts when the previous step ended): one call is enough.
        runner.advance(now)
        failure = runner.error
        if failure is not None and runner.status is RunnerStatus.FAILED and self.alarm is None:
            self.raise_alarm(
                failure.number,
                now,
                program=slot.program or "",
                line=failure.line or 0,
                level=failure.level,
                message=failure.message,
            )

    def advance_arm(self, now: float) -> None:
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
        level: ErrorLevel | None = None,
        message: str | None = None,
        detail: int = 0,
    ) -> None:
        """An error occurs: it becomes the active alarm and enters the error log. H-level
        errors switch the servo off; any error stops motion and pauses running programs.

        `level` (H/L/C) and `message` default to the error table's; a program error brings
        its own (user ERROR 9xxx numbers have no table entry)."""
        known = ERROR_MESSAGES.get(number)
        text = known.message if known is not None else (message or error_message(number))
        if level is None:
            level = error_level(number) or ErrorLevel.LOW
        alarm = Alarm(number, level, text, now, program, line, detail)
        self.alarm = alarm
        self.error_log.insert(0, alarm)
        self.jogging = None
        self.arm.stop(now)
        for slot in self.slots.values():
            self.pause_slot(slot, now)
        if alarm.level is ErrorLevel.HIGH:
            self.arm.set_servo(False, now)

    def disconnect(self, now: float) -> None:
        """The line went away (a server's client closed): the session ends and a jog stops;
        programs, servo and alarms stay, as on the controller."""
        self.advance(now)
        if self.jogging is not None:
            self.jogging = None
            self.arm.stop(self.now)
        self.is_open = False
        self.rights = False

    def turn_key(self, key: KeySwitch, now: float) -> None:
        """The operator turns the MODE key: a running program stops at its line, motion stops
        and the computer's operation rights go (it must CNTLON again) [DOC S5 §4]."""
        self.advance(now)
        if key is self.key:
            return
        self.key = key
        self.jogging = None
        self.arm.stop(self.now)
        for slot in self.slots.values():
            self.pause_slot(slot, self.now)
        self.rights = False

    def origin_lost(self, now: float) -> bool:
        """Motion asked for without an origin: L5150 becomes the alarm (once) and the
        caller refuses with it, as a real CRn-5xx answers `RUN` [TRACE K9b-C1]."""
        if self.origin_set:
            return False
        if self.alarm is None or self.alarm.number != ORIGIN_NOT_SET:
            self.raise_alarm(ORIGIN_NOT_SET, now, detail=ORIGIN_LOG_DETAIL)
        return True

    # ------------------------------------------------------------------------ slots

    def slot(self, req: Request) -> Slot:
        """The slot a request names (slot 1 for `0`, `-1` and slots beyond TASKMAX)."""
        return self.slots.get(req.slot) or self.slots[1]

    def select(self, slot: Slot, name: str) -> None:
        """Put a stored program into a slot with a fresh runner (PRGLOAD, RUN<name>)."""
        program = self.store.get(name)
        assert program is not None
        runner = self.runner_factory()
        runner.load(program.text(), program.positions)
        slot.program = name
        slot.runner = runner

    def pause_slot(self, slot: Slot, now: float) -> None:
        """STOP or an alarm: a running program halts at its line, resumable by RUN.

        Its speed settings (SPD, OVRD, JOVRD, ACCEL) stay with it: what runs meanwhile
        (EXEC, a step jog) runs at the defaults and the OP override, not at the speed the
        paused program happened to set (issue 17: jog steps crawled at 2.7 mm/s after a STOP).
        [GUESS] the real controller keeps speed settings per task slot."""
        if slot.runner is not None and slot.runner.status is RunnerStatus.RUNNING:
            slot.runner.pause(now)
            slot.held_speeds = self.arm.hold_program_speeds()

    def resume_slot(self, slot: Slot, now: float) -> None:
        """RUN on a paused program: it goes on from its line with its own speed settings."""
        assert slot.runner is not None
        if slot.held_speeds is not None:
            self.arm.restore_program_speeds(slot.held_speeds)
            slot.held_speeds = None
        slot.runner.resume(now)
        self.run_slot(slot, now)

    def reset_slot(self, slot: Slot) -> None:
        """RSTPRG / SLOTINIT: the program goes back to its first line; settings to defaults."""
        if slot.runner is not None:
            slot.runner.reset()
        slot.held_speeds = None

    def busy_with(self, name: str) -> bool:
        """A slot runs or holds paused the program `name` (it cannot be edited or deleted)."""
        return any(s.program == name and s.state is not SlotState.IDLE for s in self.slots.values())

    # ---------------------------------------------------------------------------- I/O

    def set_input(self, bit: int, value: int | bool) -> None:
        """Drive input signal `bit` (a sensor, the operator, a test, the UI). A program in
        WAIT sees it at its next `advance`."""
        self.io.set_input(bit, value)


Handler = Callable[[ControllerCore, str, Request, float], Reply]
"""A request handler: (controller, argument after the command word, request, time)."""


def program_from_text(name: str, text: str, config: SimConfig) -> Program:
    """A stored program from numbered source text (controllers created with programs)."""
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
    port = ArmPort(arm.arm)
    return lambda: Interpreter(port, io)


def _default_executor(arm: ControllerArm, io: IOState) -> StatementExecutor | None:
    """EXEC outside any loaded program: a bare interpreter on the shared arm and I/O."""
    if not isinstance(arm, SimArm):
        return None
    return Interpreter(ArmPort(arm.arm), io)
