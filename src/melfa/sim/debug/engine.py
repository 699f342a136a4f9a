"""The debugger: one program on its own simulated RV-6S, run, paused and stepped.

`Debugger` wraps an `Interpreter` on a `SimulatedArm` and drives it from an injected clock
(`clock()` returns seconds; the engine never reads the time itself):

* `run()` starts from the first line; `continue_()`, `step()` (into GOSUB), `step_over()`,
  `step_out()` and `run_to(line)` go on from a stop; `pause()` stops where the program is,
  in the middle of a move too (RUN redoes the move, as on the controller).
* `poll()` moves the program to the clock's time: at `Speed.REAL_TIME` one simulated second
  per clock second, at ``Speed.times(n)`` n of them, at `Speed.INSTANT` as fast as the
  program goes (the clock jumps from event to event) until it stops or waits. It returns a
  `Stop` the first time the program stops (breakpoint, step done, HLT, END, error, pause).
* Breakpoints are set on a line of the user's text (`break_line`) or a label
  (`break_label`). Lines are the user's own: the program is numbered for the controller
  exactly as an upload numbers it (`melfa.lang.numbering.number_tokens`, as the upload
  plan does) and the step numbers are mapped back with its step → line map.
* `variables()` is the variables panel (`view.VarView` rows, those the last stop changed
  marked), `evaluate(expr)` prints an expression, `where()` the GOSUB stack, `set_input`
  drives ``M_IN(n)`` (to release a ``WAIT``).

Stepping is the interpreter's own: `Interpreter.break_before` is asked before each step
runs, and the engine answers from its mode (stop at any step, at a depth, at a line).
What it reports (`Speed`, `Stop`, `Status`, `Breakpoint`, …) is `melfa.sim.debug.records`.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterable

from melfa.lang import ast
from melfa.lang.lexer import tokenize
from melfa.lang.numbering import number_tokens
from melfa.lang.parser import parse
from melfa.lang.points import PointDef
from melfa.lang.project import points_of
from melfa.protocol.error_table import error_code
from melfa.sim.arm import SimulatedArm
from melfa.sim.debug.records import (
    INSTANT,
    REAL_TIME,
    Breakpoint,
    DebugError,
    ErrorReport,
    Frame,
    Location,
    RunState,
    Speed,
    Status,
    Stop,
    StopReason,
    error_report,
)
from melfa.sim.debug.view import VarView, mark_changes, melfa_text, snapshot
from melfa.sim.interp import errors
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.io import IOState
from melfa.sim.interp.state import Step
from melfa.sim.interp.values import point_value
from melfa.sim.runner import RunnerStatus

DEFAULT_MAX_TIME_S = 3600.0
"""Simulated seconds a run may last before the engine stops it (a program that loops
forever at instant speed would otherwise never give control back)."""

INSTANT_POLL_S = 600.0
"""Simulated seconds one `poll` may run at instant speed (the caller polls again)…"""

INSTANT_POLL_TICKS = 250
"""… and at most this many statement budgets (`Interpreter.max_statements` each), so a
poll gives control back within a fraction of a second even in a loop that never moves."""

BUSY_STATEMENTS = 1_000_000
"""At instant speed, statements run with no move, DLY or WAIT in between before the engine
stops the program as an endless loop (`StopReason.BUSY`); simulated time would crawl."""

SLICE_S = 0.01
"""Simulated time charged to a statement budget with no event ahead (a busy loop, a WAIT)."""

WAIT_GIVE_UP_S = 1.0
"""At instant speed, simulated seconds a WAIT with nothing scheduled is watched per poll
before control goes back to the caller (who may set the input it waits for)."""


class Mode(enum.Enum):
    CONTINUE = "continue"
    STEP = "step"
    NEXT = "next"
    FINISH = "finish"
    CURSOR = "cursor"


class Debugger:
    """One program on its own simulated RV-6S, driven by an injected clock."""

    def __init__(
        self,
        program: str,
        points: str | Iterable[PointDef] = "",
        *,
        clock: Callable[[], float],
        speed: Speed = REAL_TIME,
        arm: SimulatedArm | None = None,
        io: IOState | None = None,
        max_time: float = DEFAULT_MAX_TIME_S,
    ) -> None:
        """Load `program` (the user's text, numbered or not) and its points.

        Raises `DebugError` when the program or the points cannot be loaded at all.
        """
        self.clock = clock
        self.speed = speed
        self.max_time = max_time
        self.text = program
        self.lines = program.splitlines()
        self.arm = arm if arm is not None else SimulatedArm()
        self.io = io if io is not None else IOState()
        self.interp = Interpreter(ArmPort(self.arm), self.io)
        numbering = number_tokens(tokenize(program))
        if numbering.text is None:
            first = numbering.diagnostics[0]
            raise DebugError(
                f"the program cannot be numbered: line {first.line}: {first.message}"
            ) from None
        sent = numbering.text
        self._steps_lines = numbering.step_lines
        try:
            self.interp.load(sent)
        except errors.RunError as exc:
            err = exc.to_error()
            where = f"line {exc.line}: " if getattr(exc, "line", None) else ""
            raise DebugError(f"{where}{error_code(err.number, err.level)} {err.message}") from None
        self.points = load_points(points, program)
        for p in self.points:
            self.interp.set_point(p.key, point_value(p))
        self._labels: dict[str, int] = dict(self.interp.compiler.labels)
        self._index_of_line: dict[int, int] = {}
        for i, step in enumerate(self.interp.state.steps):
            self._index_of_line.setdefault(self._line_of(step), i)
        self._breakpoints: dict[int, Breakpoint] = {}
        self._next_id = 1
        self._mode = Mode.CONTINUE
        self._mode_depth = 0
        self._cursor: int | None = None
        self._skip_once: int | None = None
        self._stopped_before: int | None = None
        self._stop: Stop | None = None
        self._wall: float | None = None
        self._busy = 0  # statement budgets run at instant speed with no event in between
        self._start_time = 0.0
        self._before: dict[str, VarView] = {}
        self._now_rows: dict[str, VarView] = {}
        self.on_start: list[Callable[[], None]] = []
        """Called when a run starts from the first line (the cell's parts go back)."""
        self._take_snapshot()

    # ------------------------------------------------------------------ breakpoints
    def break_line(self, line: int) -> Breakpoint:
        """A breakpoint on `line` of the user's text (a blank line: the next statement)."""
        index = self._index_at_or_after(line)
        return self._add(Breakpoint(self._next_id, self._line_of(self._step(index))))

    def break_label(self, label: str) -> Breakpoint:
        """A breakpoint on the line that defines ``*LABEL`` (the star is optional)."""
        name = label.strip().lstrip("*").upper()
        index = self._labels.get(name)
        if index is None:
            known = ", ".join(f"*{n}" for n in sorted(self._labels)) or "none"
            raise DebugError(f"there is no label *{name} in the program (labels: {known})")
        return self._add(Breakpoint(self._next_id, self._line_of(self._step(index)), name))

    def delete(self, breakpoint_id: int) -> None:
        if self._breakpoints.pop(breakpoint_id, None) is None:
            raise DebugError(f"there is no breakpoint {breakpoint_id}")
        self._hook()

    def clear_breakpoints(self) -> None:
        self._breakpoints.clear()
        self._hook()

    @property
    def breakpoints(self) -> tuple[Breakpoint, ...]:
        return tuple(self._breakpoints.values())

    def _add(self, bp: Breakpoint) -> Breakpoint:
        for old in self._breakpoints.values():
            if old.line == bp.line and old.label == bp.label:
                return old
        self._breakpoints[bp.id] = bp
        self._next_id += 1
        self._hook()
        return bp

    # ------------------------------------------------------------------ commands
    def run(self) -> None:
        """Start from the first line (again, if it ran before), with the breakpoints."""
        self._stop = None
        self.arm.recorder.clear()
        self.interp.start(self.interp.now, cycle=True)
        self._start_time = self.interp.now
        self._started()
        self._take_snapshot()
        self._go(Mode.CONTINUE)

    def continue_(self) -> None:
        """Go on from a stop until a breakpoint, the end or an error."""
        self._go(Mode.CONTINUE)

    def step(self) -> None:
        """Run one statement, into a GOSUB."""
        self._go(Mode.STEP)

    def step_over(self) -> None:
        """Run one statement; a GOSUB runs whole (stops inside it only at a breakpoint)."""
        self._go(Mode.NEXT)

    def step_out(self) -> None:
        """Run until the current subroutine RETURNs."""
        if self.interp.state.depth == 0 and self.state is not RunState.IDLE:
            raise DebugError("not inside a subroutine (GOSUB): nothing to finish")
        self._go(Mode.FINISH)

    def run_to(self, line: int) -> None:
        """Run until the statement on `line` (or a breakpoint on the way)."""
        self._cursor = self._index_at_or_after(line)
        self._go(Mode.CURSOR)

    def pause(self) -> Stop | None:
        """Stop where the program is (mid-move too); None if it was not running."""
        if self.interp.status is not RunnerStatus.RUNNING:
            return None
        self.poll()
        if self.interp.status is not RunnerStatus.RUNNING:
            return self._stop
        self.interp.pause(self.interp.now)
        self._settle()
        return self._stopped(StopReason.PAUSE)

    def set_input(self, bit: int, value: int) -> None:
        """Drive input ``M_IN(bit)`` (a WAIT on it goes on at the next poll)."""
        if bit < 0:
            raise DebugError(f"input numbers start at 0, got {bit}")
        self.io.set_input(bit, value)

    def set_speed(self, speed: Speed) -> None:
        self.poll()
        self.speed = speed
        if self._wall is not None:
            self._wall = self.clock()

    def _go(self, mode: Mode) -> None:
        st = self.interp.state
        if st.status is RunnerStatus.IDLE:
            self.interp.start(self.interp.now, cycle=True)
            self._start_time = self.interp.now
            self.arm.recorder.clear()
            self._started()
        elif st.status in (RunnerStatus.FINISHED, RunnerStatus.FAILED):
            raise DebugError("the program is not running (run starts it again)")
        self._mode = mode
        self._mode_depth = st.depth
        if mode is not Mode.CURSOR:
            self._cursor = None
        if st.status is RunnerStatus.PAUSED:
            # the statement the stop was before (or the move/WAIT RUN redoes) runs first
            if self._stopped_before is not None:
                self._skip_once = self._stopped_before
            elif st.resume_index is not None:
                self._skip_once = st.resume_index
            else:
                self._skip_once = None if st.remaining_delay is not None else st.pc
            self._stopped_before = None
            self.interp.resume(self.interp.now)
        else:
            self._skip_once = None
        self._stop = None
        self._busy = 0
        self._wall = self.clock()
        self._hook()

    def _started(self) -> None:
        for call in self.on_start:
            call()

    def _hook(self) -> None:
        """Ask before every step only when something could stop there (it costs a call)."""
        needed = self._mode is not Mode.CONTINUE or bool(self._breakpoints)
        self.interp.break_before = self._break_before if needed else None

    # ------------------------------------------------------------------ time
    def poll(self) -> Stop | None:
        """Run the program up to the clock's time; the `Stop` when it has just stopped."""
        if self.interp.status is not RunnerStatus.RUNNING:
            self._wall = None
            return None
        now = self.clock()
        if self.speed.factor is None:
            if self._run_instant():
                self.interp.pause(self.interp.now)
                return self._stopped(StopReason.BUSY)
        else:
            last = self._wall if self._wall is not None else now
            target = self.interp.now + max(0.0, now - last) * self.speed.factor
            self.interp.advance(target)
        self._wall = now
        if self.interp.status is RunnerStatus.RUNNING:
            if self.interp.now - self._start_time >= self.max_time:
                self.interp.pause(self.interp.now)
                self._settle()
                return self._stopped(StopReason.TIME_LIMIT)
            return None
        return self._after_stop()

    def _run_instant(self) -> bool:
        """Run from event to event (bounded per call); True when the program looks like an
        endless loop that neither moves nor waits."""
        it = self.interp
        t = it.now
        limit = t + INSTANT_POLL_S
        waited = 0.0
        busy_limit = max(1, BUSY_STATEMENTS // it.max_statements)
        for _ in range(INSTANT_POLL_TICKS):
            if it.status is not RunnerStatus.RUNNING or t > limit:
                break
            it.advance(t)
            if it.status is not RunnerStatus.RUNNING:
                break
            if t - self._start_time >= self.max_time:
                break
            nxt = it.next_event_time()
            if nxt is not None and nxt > t:
                t = nxt
                waited = 0.0
                self._busy = 0
                continue
            t += SLICE_S
            if it.waiting:
                self._busy = 0
                waited += SLICE_S
                if waited >= WAIT_GIVE_UP_S:
                    break
            else:
                self._busy += 1
                if self._busy >= busy_limit:
                    return True
        return False

    def _settle(self) -> None:
        """After a stop mid-move, let the arm finish decelerating (simulated time)."""
        end = self.arm.motion_end()
        if end is not None and end > self.interp.now:
            self.interp.advance(end)

    def _after_stop(self) -> Stop:
        status = self.interp.status
        if status is RunnerStatus.FINISHED:
            return self._stopped(StopReason.END)
        if status is RunnerStatus.FAILED:
            return self._stopped(StopReason.ERROR)
        self._settle()
        if self._stopped_before is None:
            return self._stopped(StopReason.HLT)
        bp = self._breakpoint_at(self._stopped_before)
        if bp is not None:
            return self._stopped(StopReason.BREAKPOINT, bp.id)
        return self._stopped(StopReason.STEP)

    def _stopped(self, reason: StopReason, bp: int | None = None) -> Stop:
        self._wall = None
        location = self.location
        assert location is not None
        err = self.interp.error
        report = error_report(err, location) if err is not None else None
        self._stop = Stop(reason, location, self.interp.now, report, bp)
        self._take_snapshot()
        return self._stop

    # ------------------------------------------------------------------ stepping
    def _break_before(self, index: int) -> bool:
        if self._skip_once is not None:
            skip, self._skip_once = self._skip_once, None
            if index == skip:
                return False
        if self._mode_reached(index) or self._breakpoint_at(index) is not None:
            self._stopped_before = index
            return True
        return False

    def _mode_reached(self, index: int) -> bool:
        mode = self._mode
        if mode is Mode.STEP:
            return True
        depth = self.interp.state.depth
        if mode is Mode.NEXT:
            return depth <= self._mode_depth
        if mode is Mode.FINISH:
            return depth < self._mode_depth
        if mode is Mode.CURSOR:
            return index == self._cursor
        return False

    def _breakpoint_at(self, index: int) -> Breakpoint | None:
        if not self._breakpoints:
            return None
        line = self._line_of(self._step(index))
        return next((b for b in self._breakpoints.values() if b.line == line), None)

    # ------------------------------------------------------------------ reading
    @property
    def state(self) -> RunState:
        return _STATES[self.interp.status]

    @property
    def waiting(self) -> bool:
        """The program sits in a WAIT (an input may release it)."""
        return self.interp.waiting

    @property
    def last_stop(self) -> Stop | None:
        return self._stop

    @property
    def time(self) -> float:
        """Simulated seconds since `run`."""
        return self.interp.now - self._start_time

    @property
    def location(self) -> Location | None:
        """The statement the program is at: the next to run when stopped before it, the
        one running (a move, DLY, WAIT), or the one that failed or ended the program."""
        st = self.interp.state
        if not st.steps:
            return None
        status = st.status
        if status is RunnerStatus.IDLE:
            index = 0
        elif self._stopped_before is not None and status is RunnerStatus.PAUSED:
            index = self._stopped_before
        elif status is RunnerStatus.PAUSED:
            busy = st.resume_index is not None or st.remaining_delay is not None
            index = st.current if busy else st.pc
        elif status is RunnerStatus.RUNNING and st.block is None:
            index = st.pc
        else:
            index = st.current
        return self._location(self._step(min(index, len(st.steps) - 1)))

    def status(self) -> Status:
        return Status(
            self.state,
            self.location,
            self.time,
            self.waiting,
            self.speed,
            self._stop,
            self.breakpoints,
        )

    def variables(self) -> list[VarView]:
        """The variables panel; rows the last stop changed are marked `changed`."""
        rows = self._rows()
        return mark_changes(rows, self._before)

    def evaluate(self, expression: str) -> str:
        """An expression in the program's variables, as MELFA writes the value."""
        if not expression.strip():
            raise DebugError("print what? (print M1, print P1.X, print P_CURR)")
        program = parse("PRINT " + expression)
        stmt = program.lines[0].statement if program.lines else None
        if isinstance(stmt, ast.InvalidStatement):
            raise DebugError(f"cannot read {expression.strip()!r}: {stmt.issue.message}")
        if not isinstance(stmt, ast.Print) or not stmt.items:
            raise DebugError(f"cannot read {expression.strip()!r} as an expression")
        exprs = self.interp.compiler.exprs
        try:
            return ", ".join(melfa_text(exprs.value(e)()) for e in stmt.items)
        except errors.RunError as exc:
            raise DebugError(exc.message) from None

    def where(self) -> list[Frame]:
        """The GOSUB stack, innermost first: the current statement, then each caller."""
        st = self.interp.state
        here = self.location
        if here is None:
            return []
        frames = [Frame(here, len(st.gosubs))]
        for depth, f in zip(range(len(st.gosubs) - 1, -1, -1), reversed(st.gosubs), strict=True):
            frames.append(Frame(self._location(self._step(f.called_from)), depth, f.interrupt))
        return frames

    def line_of_step(self, step: int | None) -> int | None:
        """The line of the user's text that the controller's step number `step` is."""
        return self._steps_lines.get(step) if step is not None else None

    def source_at(self, line: int) -> str:
        return self.lines[line - 1].strip() if 0 < line <= len(self.lines) else ""

    # ------------------------------------------------------------------ helpers
    def _rows(self) -> list[VarView]:
        it = self.interp
        return snapshot(it.state, it.sysvars, it.robot, it.io)

    def _take_snapshot(self) -> None:
        self._before = self._now_rows
        self._now_rows = {r.name: r for r in self._rows()}

    def _step(self, index: int) -> Step:
        return self.interp.state.steps[index]

    def _line_of(self, step: Step) -> int:
        if step.number is not None:
            line = self._steps_lines.get(step.number)
            if line is not None:
                return line
        return step.text_line

    def _location(self, step: Step) -> Location:
        line = self._line_of(step)
        return Location(line, step.number, self.source_at(line))

    def _index_at_or_after(self, line: int) -> int:
        if not 1 <= line <= len(self.lines):
            raise DebugError(f"line {line} is outside the program (1..{len(self.lines)})")
        for n in range(line, len(self.lines) + 1):
            index = self._index_of_line.get(n)
            if index is not None:
                return index
        raise DebugError(f"there is no statement on or after line {line}")


_STATES = {
    RunnerStatus.IDLE: RunState.IDLE,
    RunnerStatus.RUNNING: RunState.RUNNING,
    RunnerStatus.PAUSED: RunState.PAUSED,
    RunnerStatus.FINISHED: RunState.FINISHED,
    RunnerStatus.FAILED: RunState.FAILED,
}


def load_points(points: str | Iterable[PointDef], program: str = "") -> list[PointDef]:
    """Points from a .POS text read with its `program`'s DEF POS/JNT (`DebugError` on the
    first broken line), or as given."""
    if not isinstance(points, str):
        return list(points)
    parsed = points_of(program, points)
    if parsed.has_errors:
        first = next(d for d in parsed.diagnostics if d.is_error)
        raise DebugError(f"points line {first.line}: {first.message}")
    return list(parsed)


__all__ = [  # the debugger's records (`records`) are importable from here too
    "DEFAULT_MAX_TIME_S",
    "INSTANT",
    "REAL_TIME",
    "Breakpoint",
    "DebugError",
    "Debugger",
    "ErrorReport",
    "Frame",
    "Location",
    "RunState",
    "Speed",
    "Status",
    "Stop",
    "StopReason",
    "error_report",
    "load_points",
]
