"""The MELFA BASIC IV interpreter: runs slot 1's program on the simulated arm.

The controller drives it through the `melfa.sim.runner.ProgramRunner` protocol: `load`,
`start`/`resume` (RUN), `pause` (STOP), `reset` (RSTPRG), `advance(now)` from its clock,
and reads `status`, `line`, `error`, `waiting`. `execute` runs one EXEC statement with the
same compiled semantics.

Time: nothing here reads a clock. A move, DLY or WAIT *blocks* the program until `advance`
is called with a late enough `now`; `next_event_time()` tells a fast runner where to jump
(see `fast.py`). At most `max_statements` statements run per `advance` call, so a loop
with no motion cannot freeze the controller.

Statements are compiled once, at load, to closures (`compiler.py`); jumps are resolved to
step indices then.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Mapping

from melfa.lang import ast
from melfa.lang.parser import parse
from melfa.sim.interp import builtins, errors
from melfa.sim.interp.compiler import Compiler
from melfa.sim.interp.io import IOState
from melfa.sim.interp.machine import Watch
from melfa.sim.interp.robot import RobotPort, set_speed
from melfa.sim.interp.state import (
    Blocker,
    Delay,
    Frame,
    Motion,
    ProgramState,
    Step,
    WaitCond,
)
from melfa.sim.interp.sysvars import SystemVariables
from melfa.sim.interp.values import Value
from melfa.sim.runner import RunnerError, RunnerStatus

MAX_STATEMENTS_PER_ADVANCE = 2000
"""Statements one `advance` call may run at one instant of program time (a loop with no
motion or DLY) before giving the controller back its loop."""

STEP_TIME_S = 0.0071
"""Program time one executed step takes: one step per control period of the controller.

The period is sourced: 7.1 ms is the control period at which the controller's real-time
external control (MXT) exchanges one joint command and one feedback packet
(``../shared/docs/protocol.md`` §5, S13: tork-a's driver, "every control period (default
7.1 ms)"), and the same function exists for the RV-6S on a CR2B with the 2A-HR533 Ethernet
option [DOC S3 §3 "(8) Ethernet interface"]; RT ToolBox's oscillograph samples every
~3.5 ms, half of it (prior-art.md, mitsubishi-monitor). What no source gives is how many
steps the interpreter runs per period: one, as PRIORITY 1 runs one line per turn of the
multitask scan [S1 PRIORITY], is the stated [GUESS]. It keeps a busy loop (``10 *L`` /
``20 IF M_IN(3)=0 THEN GOTO *L``) at about 70 passes a second of program time in every mode,
instead of the hundreds of thousands a free clock gave. Moves, DLY and WAIT take their own
time on top. A trace of a real CR2B running a counting loop (`melfa doctor` reads the line
with STATE) would settle it."""


MAX_EVENTS_PER_ADVANCE = 10000
"""Move/DLY ends one `advance` call may step through; past it the program falls behind (only
a client that polls less than every few minutes with a program of very short DLYs sees it)."""


class Interpreter:
    """One slot's program on one simulated arm. Implements `ProgramRunner` and `Machine`.

    Its state is `self.state` (`state.ProgramState`): variables, stacks, blockers, clock.
    """

    def __init__(
        self,
        robot: RobotPort,
        io: IOState | None = None,
        *,
        max_statements: int = MAX_STATEMENTS_PER_ADVANCE,
        step_time: float = STEP_TIME_S,
    ) -> None:
        self.robot = robot
        self.io = io if io is not None else IOState()
        self.max_statements = max_statements
        self.step_time = step_time
        self.state = ProgramState()
        self.sysvars = SystemVariables(self.state, robot, self.io)
        self.rnd = builtins.Rnd()
        self.on_step: Callable[[Step], None] | None = None
        """Called before each program step runs (tracing; None costs nothing)."""
        self.break_before: Callable[[int], bool] | None = None
        """Asked with a step's index before it runs; True pauses the program there instead
        (a debugger's breakpoints and stepping; None costs nothing). RUN then runs it."""
        self.source: list[str] = []
        self.feed: dict[int, deque[str]] = {}
        """Lines waiting for ``INPUT #n`` by file number: what a PC or device would send."""
        self.compiler = Compiler(self)

    def feed_line(self, channel: int, line: str) -> None:
        """Script a line for ``INPUT #channel`` (a run waits in INPUT until one is there)."""
        self.feed.setdefault(channel, deque()).append(line)

    @property
    def now(self) -> float:
        """The program's clock."""
        return self.state.now

    # ------------------------------------------------------------------ loading
    def load(self, text: str, positions: Mapping[str, str] | Iterable[str] = ()) -> None:
        """Take the program text and its positions (``P1=(…)(7,0)`` texts by name, or lines).

        Raises `RunError` (a `StepError`) for a program that cannot run at all.
        """
        lines = positions.values() if isinstance(positions, Mapping) else positions
        self.load_program(parse(text), [parse(line) for line in lines])
        self.source = text.splitlines()

    def load_program(
        self, program: ast.Program, point_programs: Iterable[ast.Program] = ()
    ) -> None:
        """Load a parsed program; `point_programs` hold ``Name=(…)`` definitions."""
        st = self.state
        points: dict[str, Value] = {}
        for pp in point_programs:
            for line in pp.lines:
                if line.statement is not None:
                    self.compiler.take_point(line.statement, points, line.span.line)
        st.next_handlers.clear()
        st.types.clear()
        st.user_functions.clear()
        self.source = []
        st.steps = self.compiler.compile_program(program, points)
        st.points = points
        self.reset()

    def set_point(self, name: str, value: Value) -> None:
        """Define a point from outside (points files): kept across resets like loaded ones."""
        self.state.points[name.upper()] = value
        self.state.vars[name.upper()] = value

    # ------------------------------------------------------------------ ProgramRunner
    def start(self, now: float, *, cycle: bool = True) -> None:
        """RUN from the first step; `cycle` False repeats the program after END."""
        self.reset()
        st = self.state
        st.cycle = cycle
        st.now = now
        st.stopped_at = None
        st.status = RunnerStatus.RUNNING if st.steps else RunnerStatus.FINISHED

    def resume(self, now: float) -> None:
        """RUN while paused: continue where STOP/HLT left off (an interrupted move is redone)."""
        st = self.state
        if st.status is not RunnerStatus.PAUSED:
            return
        st.now = now
        if st.resume_index is not None:
            st.pc = st.resume_index
            st.resume_index = None
        if st.remaining_delay is not None:
            st.block = Delay(st.now + st.remaining_delay)
            st.remaining_delay = None
        st.stopped_at = None
        st.status = RunnerStatus.RUNNING

    def pause(self, now: float) -> None:
        """STOP: the arm decelerates, the program halts at the current line."""
        if self.state.status is not RunnerStatus.RUNNING:
            return
        self.advance(now)
        if self.state.status is not RunnerStatus.RUNNING:
            return
        self.halt(now)

    def halt(self, now: float) -> None:
        """Stop where the program is: a move decelerates and is redone by RUN, a DLY keeps
        what is left of it, a WAIT is asked again."""
        st = self.state
        blk = st.block
        if isinstance(blk, Motion):
            self.robot.stop(now)
            st.resume_index = st.current  # RUN redoes the interrupted move
        elif isinstance(blk, Delay):
            st.remaining_delay = max(0.0, blk.until - now)
        elif isinstance(blk, WaitCond):
            st.resume_index = st.current
        st.block = None
        st.status = RunnerStatus.PAUSED
        st.stopped_at = now

    def reset(self) -> None:
        """RSTPRG: first step, stacks and program variables cleared, speeds to defaults."""
        st = self.state
        if st.block is not None and isinstance(st.block, Motion):
            self.robot.stop(st.now)
        st.clear()
        self.sysvars.reset()
        self.robot.reset_speeds()

    @property
    def status(self) -> RunnerStatus:
        return self.state.status

    @property
    def line(self) -> int | None:
        st = self.state
        if not st.steps or st.status is RunnerStatus.IDLE:
            return st.steps[0].number if st.steps else None
        i = min(st.current, len(st.steps) - 1)
        return st.steps[i].number

    @property
    def error(self) -> RunnerError | None:
        return self.state.error

    def step_text(self, step: Step) -> str:
        """The source text of a step (without its number), for traces."""
        if 0 < step.text_line <= len(self.source):
            text = self.source[step.text_line - 1].strip()
            head, _, rest = text.partition(" ")
            return rest.strip() if head.isdigit() else text
        return ""

    @property
    def is_running(self) -> bool:
        return self.state.is_running

    @property
    def waiting(self) -> bool:
        """True while the program sits in WAIT (the controller shows stop status WAIT)."""
        return self.state.waiting

    # ------------------------------------------------------------------ time
    def advance(self, now: float) -> None:
        """Run the program up to time `now` (at most `max_statements` statements).

        The program has its own clock (`state.now`): when a move or DLY ends before `now`,
        the clock steps to that end and the next statements run then, so a chain of moves
        keeps its timing however coarsely the controller calls `advance`. Each instant the
        clock steps to gets a fresh statement budget (up to `MAX_EVENTS_PER_ADVANCE` steps).
        """
        st = self.state
        target = max(now, st.now)
        if st.status is RunnerStatus.RUNNING:
            self._run_until(target)
        self._move_clock(target)
        self.robot.set_line(self.line)

    def _move_clock(self, t: float) -> None:
        st = self.state
        if t > st.now:
            st.now = t
        self.robot.advance(st.now)
        if st.pulses:
            self._fire_pulses(st.now)

    def _run_until(self, target: float) -> None:
        st = self.state
        steps = st.steps
        n = len(steps)
        budget = self.max_statements
        events = MAX_EVENTS_PER_ADVANCE
        set_line = self.robot.set_line
        step_time = self.step_time
        while budget > 0:
            if st.block is not None:
                before = st.now
                ready = self._ready(st.block, target)
                if ready and st.now > before:
                    events -= 1  # the clock stepped to a move/DLY end: a new instant
                    budget = self.max_statements
                    if events <= 0:
                        break
            else:
                ready = True
            if not ready:
                if not st.acts or st.status is not RunnerStatus.RUNNING:
                    break
                self._move_clock(target)  # interrupts are watched while a program waits
                self._check_interrupts(st.now)
                if st.block is not None or st.status is not RunnerStatus.RUNNING:
                    break
            if st.status is not RunnerStatus.RUNNING:
                break
            if st.acts:
                self._check_interrupts(st.now)
                if st.status is not RunnerStatus.RUNNING:
                    break
            pc = st.pc
            if pc >= n:
                self._finish()
                break
            if self.break_before is not None and self.break_before(pc):
                st.status = RunnerStatus.PAUSED
                st.stopped_at = st.now
                break
            st.current = pc
            st.pc = pc + 1
            step = steps[pc]
            set_line(step.number)
            if self.on_step is not None:
                self.on_step(step)
            try:
                step.run()
            except errors.RunError as exc:
                self._fail(exc, step.number)
                break
            budget -= 1
            if st.status is not RunnerStatus.RUNNING:
                break
            if step_time and st.block is None:
                # The step took its time; what follows runs when the clock gets there.
                st.now += step_time
                if st.now > target:
                    break

    def _ready(self, blk: Blocker, target: float) -> bool:
        """Whether the program may go on by `target`; moves the program clock to when."""
        st = self.state
        if isinstance(blk, Delay):
            if blk.until > target:
                return False
            self._move_clock(blk.until)
            st.block = None
            return True
        if isinstance(blk, Motion):
            ends = blk.until <= target
            self._move_clock(min(blk.until, target))
            if blk.watch is not None:
                cond, action = blk.watch
                try:
                    if cond():
                        blk.watch = None
                        action()
                except errors.RunError as exc:
                    self._fail(exc, st.steps[st.current].number)
                    return False
                if st.block is not blk:  # SKIP or HLT acted on the move
                    return st.status is RunnerStatus.RUNNING and st.block is None
            if not ends:
                return False
            st.block = None
            return True
        self._move_clock(target)
        try:
            ok = blk.condition()
        except errors.RunError as exc:
            self._fail(exc, st.steps[st.current].number)
            return False
        if ok:
            st.block = None
        return ok

    def next_event_time(self) -> float | None:
        """When something scheduled happens next (move end, DLY end, pulse), if anything."""
        st = self.state
        times = [t for t, _ in st.pulses]
        blk = st.block
        if isinstance(blk, Motion | Delay):
            times.append(blk.until)
        return min(times) if times else None

    def _fire_pulses(self, now: float) -> None:
        st = self.state
        due = [p for p in st.pulses if p[0] <= now]
        if due:
            st.pulses[:] = [p for p in st.pulses if p[0] > now]
            for _, action in sorted(due, key=lambda p: p[0]):
                action()

    def _finish(self) -> None:
        """END or past the last step: speeds back to defaults [S1 END]; repeat if asked."""
        st = self.state
        self.robot.reset_speeds()
        st.gosubs.clear()
        st.loops.clear()
        if st.cycle:
            st.status = RunnerStatus.FINISHED
            st.stopped_at = st.now
        else:
            st.pc = 0

    def _fail(self, exc: errors.RunError, line: int | None) -> None:
        st = self.state
        err = exc.to_error(line)
        if exc.error_level is errors.ErrorLevel.CAUTION:
            st.caution = err  # caution level: recorded, the program continues
            return
        st.error = err
        if isinstance(st.block, Motion) or self.robot.motion_end() is not None:
            self.robot.stop(st.now)
        st.block = None
        st.status = RunnerStatus.FAILED
        st.stopped_at = st.now
        if exc.error_level is errors.ErrorLevel.HIGH:
            self.robot.set_servo(False, st.now)  # H level errors turn the servo off

    # ------------------------------------------------------------------ interrupts
    def _check_interrupts(self, now: float) -> None:
        st = self.state
        if not st.acts_master:
            return
        for prio in sorted(st.acts):
            act = st.acts[prio]
            if not act.enabled:
                continue
            if st.act_mask is not None and prio >= st.act_mask:
                continue
            if not act.condition():
                continue
            blk = st.block
            resume_at = st.pc
            if isinstance(blk, Motion):
                if act.mode == "L":
                    return  # [GUESS] L: the move finishes before the interrupt is taken
                self.robot.stop(now)
                resume_at = st.current
            elif isinstance(blk, WaitCond | Delay):
                resume_at = st.current if isinstance(blk, WaitCond) else st.pc
            st.block = None
            if act.gosub:
                st.push_frame(Frame(st.pc, len(st.loops), prio, resume_at, st.current))
                st.act_mask = prio
            st.pc = act.target
            return

    # ------------------------------------------------------------------ Machine
    def end(self) -> None:
        self._finish()
        if not self.state.cycle:
            return
        self.state.pc = len(self.state.steps)

    def set_speed(self, what: str, value: Value) -> None:
        """OVRD/JOVRD/SPD as a statement would set them."""
        set_speed(self.robot, what, value)

    def start_motion(self, move: Callable[[float], float], watch: Watch | None = None) -> None:
        """Begin a move and block the program until it ends."""
        if not self.robot.servo_on:
            raise errors.RunError(errors.SERVO_OFF, "the servo is OFF (SERVO ON first)")
        st = self.state
        st.skipped = 0
        st.block = Motion(move(st.now), watch)

    def skip_motion(self) -> None:
        """SKIP (from WTH/WTHIF): stop the move and go on with the next line."""
        st = self.state
        self.robot.stop(st.now)
        st.skipped = 1
        st.block = None

    # ------------------------------------------------------------------ EXEC
    def execute(self, statement: str, now: float) -> None:
        """EXEC: run one statement now, in this slot's variables; moves start and return.

        Raises `RunError` (a `StepError`) when the statement is refused.
        """
        self.advance(now)
        program = parse(statement)
        lines = [ln for ln in program.lines if ln.statement is not None]
        if not lines and any(ln.comment is not None for ln in program.lines):
            return  # ``EXECREM Waiting...``: a comment is accepted and does nothing [CODE S6]
        if len(lines) != 1:
            raise errors.RunError(errors.SYNTAX_ERROR, "EXEC takes exactly one statement")
        stmt = lines[0].statement
        assert stmt is not None
        if isinstance(
            stmt,
            ast.Goto
            | ast.Gosub
            | ast.OnJump
            | ast.Return
            | ast.For
            | ast.Next
            | ast.While
            | ast.Wend
            | ast.Select
            | ast.Case
            | ast.Break
            | ast.Default
            | ast.EndSelect
            | ast.Else
            | ast.EndIf
            | ast.Wait,
        ) or (isinstance(stmt, ast.If) and stmt.is_block):
            raise errors.RunError(
                errors.SYNTAX_ERROR, "flow-control statements cannot be run with EXEC"
            )
        run = self.compiler.compile_single(stmt)
        st = self.state
        saved_block, saved_pc, saved_status = st.block, st.pc, st.status
        st.status = RunnerStatus.RUNNING
        try:
            run()
        finally:
            # a move started by EXEC goes on by itself; the program's own state is untouched
            st.block = saved_block
            st.pc = saved_pc
            st.status = saved_status
