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

import enum
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass

from melfa.lang import ast
from melfa.lang.parser import parse
from melfa.sim.interp import builtins, errors, posmath
from melfa.sim.interp.io import IOState
from melfa.sim.interp.robot import RobotPort
from melfa.sim.interp.sysvars import SystemVariables
from melfa.sim.interp.values import (
    Joints,
    Position,
    Value,
    VarType,
    round_half_away,
    type_name,
)
from melfa.sim.runner import RunnerError, RunnerStatus

MAX_STATEMENTS_PER_ADVANCE = 2000
"""Statements one `advance` call may run at one instant of program time (a loop with no
motion or DLY) before giving the controller back its loop."""

MAX_EVENTS_PER_ADVANCE = 10000
"""Move/DLY ends one `advance` call may step through; past it the program falls behind (only
a client that polls less than every few minutes with a program of very short DLYs sees it)."""

ARRAY_LOWER_BOUND = 1
"""[GUESS] First subscript of a DIM array (DIM M(10) has M(1)…M(10))."""

MAX_DIM_SIZE = 999  # DIM subscripts 1…999 [S1 DIM]


class StepKind(enum.Enum):
    PLAIN = "plain"
    MOTION = "motion"


@dataclass(slots=True)
class Step:
    """One executable program line."""

    number: int | None  # step number shown as the line (text line when unnumbered)
    run: Callable[[], None]
    text_line: int = 0  # 1-based line of the program text


class Array:
    """A DIM array: up to 3 dimensions, 1-based subscripts, elements undefined until set."""

    def __init__(self, sizes: tuple[int, ...], vtype: VarType) -> None:
        self.sizes = sizes
        self.vtype = vtype
        self.data: dict[tuple[int, ...], Value] = {}

    def key(self, name: str, subs: list[Value]) -> tuple[int, ...]:
        if len(subs) != len(self.sizes):
            raise errors.RunError(
                errors.ARRAY_ELEMENT,
                f"{name} has {len(self.sizes)} dimension(s), got {len(subs)} subscript(s)",
            )
        out = []
        for s, size in zip(subs, self.sizes, strict=True):
            if not isinstance(s, int | float):
                raise errors.RunError(errors.TYPE_COMBINATION, "array subscripts are numbers")
            i = round_half_away(s)
            if not ARRAY_LOWER_BOUND <= i <= size:
                raise errors.RunError(
                    errors.ARRAY_ELEMENT,
                    f"subscript {i} of {name} is outside {ARRAY_LOWER_BOUND}..{size}",
                )
            out.append(i)
        return tuple(out)

    def get(self, name: str, subs: list[Value]) -> Value:
        key = self.key(name, subs)
        try:
            return self.data[key]
        except KeyError:
            shown = ",".join(str(i) for i in key)
            raise errors.RunError(
                errors.UNDEFINED_VARIABLE, f"{name}({shown}) has no value"
            ) from None


@dataclass(slots=True)
class PalletDef:
    start: Position
    end_a: Position
    end_b: Position
    diagonal: Position | None
    count_a: int
    count_b: int
    direction: int


@dataclass(slots=True)
class ActDef:
    priority: int
    condition: Callable[[], bool]
    gosub: bool
    target: int
    mode: str | None
    enabled: bool = False


# --- blockers: what a program waits for ---------------------------------------------------


@dataclass(slots=True)
class Delay:
    until: float


@dataclass(slots=True)
class Motion:
    """Waiting for the arm until `until`; `watch` is a WTHIF (condition, action)."""

    until: float
    watch: tuple[Callable[[], bool], Callable[[], None]] | None = None


@dataclass(slots=True)
class WaitCond:
    condition: Callable[[], bool]


Blocker = Delay | Motion | WaitCond


@dataclass(slots=True)
class Frame:
    """A GOSUB return point; `interrupt` is the ACT priority when entered by DEF ACT."""

    return_to: int
    loops: int
    interrupt: int | None = None
    interrupted_at: int = 0


@dataclass(slots=True)
class Loop:
    start: int  # index of the FOR/WHILE step
    counter: str | None = None
    end: float = 0.0
    step: float = 1.0


class Interpreter:
    """One slot's program on one simulated arm. Implements `ProgramRunner`."""

    def __init__(
        self,
        robot: RobotPort,
        io: IOState | None = None,
        *,
        max_statements: int = MAX_STATEMENTS_PER_ADVANCE,
    ) -> None:
        self.robot = robot
        self.io = io if io is not None else IOState()
        self.max_statements = max_statements
        self.now = 0.0
        # variables (dicts are cleared in place: compiled closures hold them)
        self.vars: dict[str, Value] = {}
        self.types: dict[str, VarType] = {}
        self.arrays: dict[str, Array] = {}
        self.user_functions: dict[str, Callable[[list[Value]], Value]] = {}
        self.pallets: dict[int, PalletDef] = {}
        self.acts: dict[int, ActDef] = {}
        self.acts_master = True  # [GUESS] ACT 0 (master switch) starts enabled
        self.points: dict[str, Value] = {}
        self.sysvars = SystemVariables(self)
        self.rnd = builtins.Rnd()
        self.on_step: Callable[[Step], None] | None = None
        """Called before each program step runs (tracing; None costs nothing)."""
        self.source: list[str] = []
        self.console: list[str] = []
        """What PRINT wrote (the simulator has no serial port to write to)."""
        # program
        self.steps: list[Step] = []
        self.pc = 0
        self.current = 0
        self.next_handlers: dict[int, Callable[[int], None]] = {}
        self.gosubs: list[Frame] = []
        self.loops: list[Loop] = []
        self.block: Blocker | None = None
        self.resume_index: int | None = None
        self.remaining_delay: float | None = None
        self.pulses: list[tuple[float, Callable[[], None]]] = []
        self.skipped = 0
        self.caution: RunnerError | None = None
        self._status = RunnerStatus.IDLE
        self._error: RunnerError | None = None
        self._cycle = True
        self.stopped_at: float | None = None
        """Program time when the program last stopped running (END, an error, HLT, STOP),
        which `now` may have passed since; None while it runs."""
        self._act_mask: int | None = None  # priorities >= this are masked (in a handler)
        from melfa.sim.interp.compiler import Compiler

        self.compiler = Compiler(self)

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
        points: dict[str, Value] = {}
        for pp in point_programs:
            for line in pp.lines:
                if line.statement is not None:
                    self._take_point(line.statement, points, line.span.line)
        self.next_handlers.clear()
        self.types.clear()
        self.user_functions.clear()
        self.source = []
        self.steps = self.compiler.compile_program(program, points)
        self.points = points
        self.reset()

    def set_point(self, name: str, value: Value) -> None:
        """Define a point from outside (points files): kept across resets like loaded ones."""
        self.points[name.upper()] = value
        self.vars[name.upper()] = value

    def _take_point(self, stmt: ast.Statement, points: dict[str, Value], line: int) -> None:
        target: ast.Name | None = None
        value: ast.Expr | None = None
        if isinstance(stmt, ast.Assign) and isinstance(stmt.target, ast.Name):
            target, value = stmt.target, stmt.value
        elif isinstance(stmt, ast.DefVar) and len(stmt.names) == 1 and stmt.value is not None:
            target, value = stmt.names[0], stmt.value
        if target is None or not isinstance(value, ast.PositionLiteral):
            raise errors.RunError(
                errors.SYNTAX_ERROR,
                f"position line {line} is not a point definition Name=(…)",
                line=line,
            )
        hint = VarType.JOINT if target.name.startswith("J") else VarType.POSITION
        points[target.name] = self.compiler.exprs.value(value, hint)()

    # ------------------------------------------------------------------ ProgramRunner
    def start(self, now: float, *, cycle: bool = True) -> None:
        """RUN from the first step; `cycle` False repeats the program after END."""
        self.reset()
        self._cycle = cycle
        self.now = now
        self.stopped_at = None
        self._status = RunnerStatus.RUNNING if self.steps else RunnerStatus.FINISHED

    def resume(self, now: float) -> None:
        """RUN while paused: continue where STOP/HLT left off (an interrupted move is redone)."""
        if self._status is not RunnerStatus.PAUSED:
            return
        self.now = now
        if self.resume_index is not None:
            self.pc = self.resume_index
            self.resume_index = None
        if self.remaining_delay is not None:
            self.block = Delay(now + self.remaining_delay)
            self.remaining_delay = None
        self.stopped_at = None
        self._status = RunnerStatus.RUNNING

    def pause(self, now: float) -> None:
        """STOP: the arm decelerates, the program halts at the current line."""
        if self._status is not RunnerStatus.RUNNING:
            return
        self.advance(now)
        if self._status is not RunnerStatus.RUNNING:
            return
        self._halt(now)

    def _halt(self, now: float) -> None:
        blk = self.block
        if isinstance(blk, Motion):
            self.robot.stop(now)
            self.resume_index = self.current  # RUN redoes the interrupted move
        elif isinstance(blk, Delay):
            self.remaining_delay = max(0.0, blk.until - now)
        elif isinstance(blk, WaitCond):
            self.resume_index = self.current
        self.block = None
        self._status = RunnerStatus.PAUSED
        self.stopped_at = now

    def reset(self) -> None:
        """RSTPRG: first step, stacks and program variables cleared, speeds to defaults."""
        if self.block is not None and isinstance(self.block, Motion):
            self.robot.stop(self.now)
        self.pc = 0
        self.current = 0
        self.gosubs.clear()
        self.loops.clear()
        self.block = None
        self.resume_index = None
        self.remaining_delay = None
        self.pulses.clear()
        self.vars.clear()
        self.vars.update(self.points)
        self.arrays.clear()
        self.pallets.clear()
        self.acts.clear()
        self.acts_master = True
        self._act_mask = None
        self.sysvars.reset()
        self.skipped = 0
        self.caution = None
        self._error = None
        self.robot.reset_speeds()
        self._status = RunnerStatus.IDLE

    @property
    def status(self) -> RunnerStatus:
        return self._status

    @property
    def line(self) -> int | None:
        if not self.steps or self._status is RunnerStatus.IDLE:
            return self.steps[0].number if self.steps else None
        i = min(self.current, len(self.steps) - 1)
        return self.steps[i].number

    @property
    def error(self) -> RunnerError | None:
        return self._error

    def step_text(self, step: Step) -> str:
        """The source text of a step (without its number), for traces."""
        if 0 < step.text_line <= len(self.source):
            text = self.source[step.text_line - 1].strip()
            head, _, rest = text.partition(" ")
            return rest.strip() if head.isdigit() else text
        return ""

    @property
    def is_running(self) -> bool:
        return self._status is RunnerStatus.RUNNING

    @property
    def waiting(self) -> bool:
        """True while the program sits in WAIT (the controller shows stop status WAIT)."""
        return self._status is RunnerStatus.RUNNING and isinstance(self.block, WaitCond)

    # ------------------------------------------------------------------ time
    def advance(self, now: float) -> None:
        """Run the program up to time `now` (at most `max_statements` statements).

        The program has its own clock (`self.now`): when a move or DLY ends before `now`,
        the clock steps to that end and the next statements run then, so a chain of moves
        keeps its timing however coarsely the controller calls `advance`. Each instant the
        clock steps to gets a fresh statement budget (up to `MAX_EVENTS_PER_ADVANCE` steps).
        """
        target = max(now, self.now)
        if self._status is RunnerStatus.RUNNING:
            self._run_until(target)
        self._move_clock(target)
        self.robot.set_line(self.line)

    def _move_clock(self, t: float) -> None:
        if t > self.now:
            self.now = t
        self.robot.advance(self.now)
        if self.pulses:
            self._fire_pulses(self.now)

    def _run_until(self, target: float) -> None:
        steps = self.steps
        n = len(steps)
        budget = self.max_statements
        events = MAX_EVENTS_PER_ADVANCE
        set_line = self.robot.set_line
        while budget > 0:
            if self.block is not None:
                before = self.now
                ready = self._ready(self.block, target)
                if ready and self.now > before:
                    events -= 1  # the clock stepped to a move/DLY end: a new instant
                    budget = self.max_statements
                    if events <= 0:
                        break
            else:
                ready = True
            if not ready:
                if not self.acts or self._status is not RunnerStatus.RUNNING:
                    break
                self._move_clock(target)  # interrupts are watched while a program waits
                self._check_interrupts(self.now)
                if self.block is not None or self._status is not RunnerStatus.RUNNING:
                    break
            if self._status is not RunnerStatus.RUNNING:
                break
            if self.acts:
                self._check_interrupts(self.now)
                if self._status is not RunnerStatus.RUNNING:
                    break
            pc = self.pc
            if pc >= n:
                self._finish()
                break
            self.current = pc
            self.pc = pc + 1
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
            if self._status is not RunnerStatus.RUNNING:
                break

    def _ready(self, blk: Blocker, target: float) -> bool:
        """Whether the program may go on by `target`; moves the program clock to when."""
        if isinstance(blk, Delay):
            if blk.until > target:
                return False
            self._move_clock(blk.until)
            self.block = None
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
                    self._fail(exc, self.steps[self.current].number)
                    return False
                if self.block is not blk:  # SKIP or HLT acted on the move
                    return self._status is RunnerStatus.RUNNING and self.block is None
            if not ends:
                return False
            self.block = None
            return True
        self._move_clock(target)
        try:
            ok = blk.condition()
        except errors.RunError as exc:
            self._fail(exc, self.steps[self.current].number)
            return False
        if ok:
            self.block = None
        return ok

    def next_event_time(self) -> float | None:
        """When something scheduled happens next (move end, DLY end, pulse), if anything."""
        times = [t for t, _ in self.pulses]
        blk = self.block
        if isinstance(blk, Motion | Delay):
            times.append(blk.until)
        return min(times) if times else None

    def _fire_pulses(self, now: float) -> None:
        due = [p for p in self.pulses if p[0] <= now]
        if due:
            self.pulses = [p for p in self.pulses if p[0] > now]
            for _, action in sorted(due, key=lambda p: p[0]):
                action()

    def _finish(self) -> None:
        """END or past the last step: speeds back to defaults [S1 END]; repeat if asked."""
        self.robot.reset_speeds()
        self.gosubs.clear()
        self.loops.clear()
        if self._cycle:
            self._status = RunnerStatus.FINISHED
            self.stopped_at = self.now
        else:
            self.pc = 0

    def _fail(self, exc: errors.RunError, line: int | None) -> None:
        err = exc.to_error(line)
        if exc.error_level is errors.ErrorLevel.CAUTION:
            self.caution = err  # caution level: recorded, the program continues
            return
        self._error = err
        if isinstance(self.block, Motion) or self.robot.motion_end() is not None:
            self.robot.stop(self.now)
        self.block = None
        self._status = RunnerStatus.FAILED
        self.stopped_at = self.now
        if exc.error_level is errors.ErrorLevel.HIGH:
            self.robot.set_servo(False, self.now)  # H level errors turn the servo off

    # ------------------------------------------------------------------ interrupts
    def _check_interrupts(self, now: float) -> None:
        if not self.acts_master:
            return
        for prio in sorted(self.acts):
            act = self.acts[prio]
            if not act.enabled:
                continue
            if self._act_mask is not None and prio >= self._act_mask:
                continue
            if not act.condition():
                continue
            blk = self.block
            resume_at = self.pc
            if isinstance(blk, Motion):
                if act.mode == "L":
                    return  # [GUESS] L: the move finishes before the interrupt is taken
                self.robot.stop(now)
                resume_at = self.current
            elif isinstance(blk, WaitCond | Delay):
                resume_at = self.current if isinstance(blk, WaitCond) else self.pc
            self.block = None
            if act.gosub:
                self._push_frame(Frame(self.pc, len(self.loops), prio, resume_at))
                self._act_mask = prio
            self.pc = act.target
            return

    def _push_frame(self, frame: Frame) -> None:
        if len(self.gosubs) >= errors.MAX_GOSUB_DEPTH:
            raise errors.RunError(errors.GOSUB_NESTING_OVER, "GOSUB nesting is too deep")
        self.gosubs.append(frame)

    def gosub(self, target: int) -> None:
        self._push_frame(Frame(self.pc, len(self.loops)))
        self.pc = target

    def return_(self, mode: int | None) -> None:
        if not self.gosubs:
            raise errors.RunError(errors.RETURN_WITHOUT_GOSUB, "RETURN without GOSUB")
        frame = self.gosubs.pop()
        del self.loops[frame.loops :]
        if frame.interrupt is not None:
            self._act_mask = next(
                (f.interrupt for f in reversed(self.gosubs) if f.interrupt is not None), None
            )
            # RETURN 0: back to the interrupted line; RETURN 1 (or plain): the next one
            self.pc = frame.interrupted_at if mode == 0 else frame.return_to
            return
        self.pc = frame.return_to

    # ------------------------------------------------------------------ helpers for steps
    def hold(self) -> None:
        """HLT: pause; RUN continues with the next line."""
        self._status = RunnerStatus.PAUSED
        self.stopped_at = self.now

    def end(self) -> None:
        self._finish()
        if not self._cycle:
            return
        self.pc = len(self.steps)

    def set_speed(self, what: str, value: Value) -> None:
        if not isinstance(value, int | float):
            raise errors.RunError(errors.TYPE_COMBINATION, f"{what} needs a number")
        v = float(value)
        if what in ("OVRD", "JOVRD"):
            if not 0 < v <= 100:  # OVRD 0 or >100 is an error [S1 OVRD]
                raise errors.RunError(
                    errors.ARGUMENT_OUT_OF_RANGE, f"{what} must be 1..100 %, got {value}"
                )
            if what == "OVRD":
                self.robot.set_speeds(ovrd=v)
            else:
                self.robot.set_speeds(jovrd=v)
        elif what == "SPD":
            if v <= 0:
                raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"SPD must be > 0, got {value}")
            self.robot.set_speeds(spd=v)

    def start_motion(
        self,
        move: Callable[[float], float],
        watch: tuple[Callable[[], bool], Callable[[], None]] | None = None,
    ) -> None:
        """Begin a move and block the program until it ends."""
        if not self.robot.servo_on:
            raise errors.RunError(errors.SERVO_OFF, "the servo is OFF (SERVO ON first)")
        self.skipped = 0
        self.block = Motion(move(self.now), watch)

    def skip_motion(self) -> None:
        """SKIP (from WTH/WTHIF): stop the move and go on with the next line."""
        self.robot.stop(self.now)
        self.skipped = 1
        self.block = None

    def pallet_point(self, number: int, index: int) -> Position:
        plt = self.pallets.get(number)
        if plt is None:
            raise errors.RunError(errors.UNDEFINED_PALLET, f"pallet {number} is not defined")
        na, nb = plt.count_a, plt.count_b
        if not 1 <= index <= na * nb:
            raise errors.RunError(
                errors.ARGUMENT_OUT_OF_RANGE, f"pallet {number} has grid points 1..{na * nb}"
            )
        i, j = (index - 1) % na, (index - 1) // na
        if plt.direction == 1 and j % 2 == 1:  # zigzag: every other row backwards
            i = na - 1 - i
        u = i / (na - 1) if na > 1 else 0.0
        v = j / (nb - 1) if nb > 1 else 0.0
        s, a, b = plt.start, plt.end_a, plt.end_b
        d = plt.diagonal or posmath.subtract(posmath.add(a, b), s)
        w = ((1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v)

        def mix(attr: str) -> float:
            return float(sum(wk * getattr(p, attr) for wk, p in zip(w, (s, a, b, d), strict=True)))

        return Position(
            mix("x"), mix("y"), mix("z"), mix("a"), mix("b"), mix("c"), mix("l1"), mix("l2"),
            s.fl1, s.fl2,
        )  # fmt: skip

    def robot_function(
        self, name: str, args: list[Callable[[], Value]]
    ) -> Callable[[], Value] | None:
        """Functions that need the arm's kinematics: PTOJ, JTOP, POSCQ."""
        robot = self.robot
        if name not in ("PTOJ", "JTOP", "POSCQ") or len(args) != 1:
            return None
        arg = args[0]
        if name == "PTOJ":

            def ptoj() -> Value:
                p = arg()
                if not isinstance(p, Position):
                    raise errors.RunError(errors.TYPE_COMBINATION, "PTOJ needs a position")
                return robot.to_joints(p)

            return ptoj
        if name == "JTOP":

            def jtop() -> Value:
                j = arg()
                if not isinstance(j, Joints):
                    raise errors.RunError(errors.TYPE_COMBINATION, "JTOP needs a joint position")
                return robot.to_position(j)

            return jtop

        def poscq() -> Value:
            p = arg()
            if isinstance(p, Joints):
                p = robot.to_position(p)
            if not isinstance(p, Position):
                raise errors.RunError(
                    errors.TYPE_COMBINATION, f"POSCQ needs a position, not a {type_name(p)}"
                )
            try:
                robot.to_joints(p)
            except errors.RunError:
                return 0
            return 1

        return poscq

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
        saved_block, saved_pc, saved_status = self.block, self.pc, self._status
        self._status = RunnerStatus.RUNNING
        try:
            run()
        finally:
            # a move started by EXEC goes on by itself; the program's own state is untouched
            self.block = saved_block
            self.pc = saved_pc
            self._status = saved_status
