"""The run-time state of one program: variables, scopes, stacks, what it waits for.

`ProgramState` is plain data with the few operations that only touch it (GOSUB/RETURN
frames, pallets, HLT). The interpreter (`interpreter.py`) drives it through time, the
compiled statements (`compiler.py` and its mixins) read and write it, and a debugger
(`melfa.sim.debug`) inspects it between steps: the call stack (`gosubs`), the open loops
(`loops`), what the program is blocked on (`block`) and the next step (`pc`) are all here,
so stepping, pausing mid-motion and showing scopes need no access to the interpreter's
internals. Nothing here reads a clock or touches the arm.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass

from melfa.lang import model as lang_model
from melfa.sim.interp import errors, posmath
from melfa.sim.interp.values import Position, Value, VarType, round_half_away
from melfa.sim.runner import RunnerError, RunnerStatus

ARRAY_LOWER_BOUND = 1
"""[GUESS] First subscript of a DIM array (DIM M(10) has M(1)…M(10))."""

MAX_DIM_SIZE = lang_model.MAX_DIM_SIZE  # DIM subscripts 1…999: the language's limit


class StepKind(enum.Enum):
    PLAIN = "plain"
    MOTION = "motion"


@dataclass(slots=True)
class Step:
    """One executable program line."""

    number: int | None  # step number shown as the line (text line when unnumbered)
    run: Callable[[], None]
    text_line: int = 0  # 1-based line of the program text
    label: str | None = None  # the line's *LABEL, if any


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
    called_from: int = 0  # index of the GOSUB step (or the step an interrupt came at)


@dataclass(slots=True)
class Loop:
    start: int  # index of the FOR/WHILE step
    counter: str | None = None
    end: float = 0.0
    step: float = 1.0


class ProgramState:
    """Everything a running program has: read by the statements, driven by the interpreter.

    Dicts and lists are cleared in place, never replaced: compiled closures hold them.
    """

    def __init__(self) -> None:
        self.now = 0.0
        """The program's own clock (seconds of the injected clock)."""
        self.vars: dict[str, Value] = {}
        self.types: dict[str, VarType] = {}
        self.arrays: dict[str, Array] = {}
        self.user_functions: dict[str, Callable[[list[Value]], Value]] = {}
        self.pallets: dict[int, PalletDef] = {}
        self.acts: dict[int, ActDef] = {}
        self.acts_master = True  # [GUESS] ACT 0 (master switch) starts enabled
        self.act_mask: int | None = None  # priorities >= this are masked (in a handler)
        self.points: dict[str, Value] = {}
        self.console: list[str] = []
        """What PRINT wrote (the simulator has no serial port to write to)."""
        self.steps: list[Step] = []
        self.pc = 0
        """Index of the next step to run."""
        self.current = 0
        """Index of the step running (or last run)."""
        self.next_handlers: dict[int, Callable[[int], None]] = {}
        self.gosubs: list[Frame] = []
        self.loops: list[Loop] = []
        self.block: Blocker | None = None
        self.resume_index: int | None = None
        self.remaining_delay: float | None = None
        self.pulses: list[tuple[float, Callable[[], None]]] = []
        self.skipped = 0
        self.caution: RunnerError | None = None
        self.status = RunnerStatus.IDLE
        self.error: RunnerError | None = None
        self.cycle = True
        self.stopped_at: float | None = None
        """Program time when the program last stopped running (END, an error, HLT, STOP),
        which `now` may have passed since; None while it runs."""

    def clear(self) -> None:
        """RSTPRG: first step, stacks and program variables cleared (points kept)."""
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
        self.act_mask = None
        self.skipped = 0
        self.caution = None
        self.error = None
        self.status = RunnerStatus.IDLE

    # ------------------------------------------------------------------ reading
    @property
    def is_running(self) -> bool:
        return self.status is RunnerStatus.RUNNING

    @property
    def waiting(self) -> bool:
        """True while the program sits in WAIT (the controller shows stop status WAIT)."""
        return self.status is RunnerStatus.RUNNING and isinstance(self.block, WaitCond)

    @property
    def depth(self) -> int:
        """How many GOSUBs (and ACT handlers) deep the program is."""
        return len(self.gosubs)

    # ------------------------------------------------------------------ operations
    def push_frame(self, frame: Frame) -> None:
        if len(self.gosubs) >= errors.MAX_GOSUB_DEPTH:
            raise errors.RunError(errors.GOSUB_NESTING_OVER, "GOSUB nesting is too deep")
        self.gosubs.append(frame)

    def gosub(self, target: int) -> None:
        self.push_frame(Frame(self.pc, len(self.loops), called_from=self.current))
        self.pc = target

    def return_(self, mode: int | None) -> None:
        if not self.gosubs:
            raise errors.RunError(errors.RETURN_WITHOUT_GOSUB, "RETURN without GOSUB")
        frame = self.gosubs.pop()
        del self.loops[frame.loops :]
        if frame.interrupt is not None:
            self.act_mask = next(
                (f.interrupt for f in reversed(self.gosubs) if f.interrupt is not None), None
            )
            # RETURN 0: back to the interrupted line; RETURN 1 (or plain): the next one
            self.pc = frame.interrupted_at if mode == 0 else frame.return_to
            return
        self.pc = frame.return_to

    def hold(self) -> None:
        """HLT: pause; RUN continues with the next line."""
        self.status = RunnerStatus.PAUSED
        self.stopped_at = self.now

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
