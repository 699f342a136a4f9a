"""The hooks between the virtual controller and the interpreter.

The controller owns the protocol state (sessions, rights, slots, alarms); the interpreter
(`melfa.sim.interp`, owned by the interp engineer) owns what a program *does*. Two narrow
interfaces join them:

- `ProgramRunner`: one per task slot, driven by RUN / STOP / RSTPRG / SLOTINIT and by the
  controller's clock (`advance(now)`).
- `StatementExecutor`: runs one `EXEC<statement>` with the same semantics as a program line
  (one evaluator, not two).

Both are `typing.Protocol`s, so the interpreter implements them without importing this
module. `LineWalker` is the stand-in runner used until an interpreter is plugged in: it
walks the steps in order with no motion, so RUN, STATE and STOP are observable.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from melfa.protocol.error_table import ErrorLevel


class RunnerStatus(enum.Enum):
    """Where a slot's program is."""

    IDLE = "idle"  # loaded, not started (or reset)
    RUNNING = "running"
    PAUSED = "paused"  # stopped by STOP, resumable by RUN
    FINISHED = "finished"  # reached END / the last step in cycle mode
    FAILED = "failed"  # stopped by a run-time error (see `error`)


@dataclass(frozen=True, slots=True)
class RunnerError:
    """A run-time error: the controller's number, its level (H/L/C), line, text."""

    number: int
    message: str
    line: int | None = None
    level: ErrorLevel = ErrorLevel.LOW


@runtime_checkable
class ProgramRunner(Protocol):
    """What the controller calls on a slot's program.

    The controller calls `advance(now)` before answering every request, with `now` in
    seconds from its injected clock, so calls may be far apart; the runner moves the shared
    `SimulatedArm` and never reads a clock of its own.
    """

    def load(self, text: str, positions: Mapping[str, str]) -> None:
        """Take the program text (numbered steps) and its positions (`P1=(…)(7,0)` by name).

        Raise `StepError` for a program that cannot run at all."""

    def start(self, now: float, *, cycle: bool) -> None:
        """Start from the first step. `cycle`: run once (RUN…;1) or repeat (RUN…;0)."""

    def resume(self, now: float) -> None:
        """Continue a paused program (RUN while paused)."""

    def pause(self, now: float) -> None:
        """STOP: halt motion and execution where they are; resumable."""

    def reset(self) -> None:
        """RSTPRG / SLOTINIT: back to the first step, variables cleared."""

    def advance(self, now: float) -> None:
        """Execute up to time `now`. A statement that starts inside this call starts when
        the previous one ended (a DLY 0.5 after a DLY 0.5 ends at 1.0), not at `now`: the
        runner's timing must not depend on how often it is polled."""

    @property
    def status(self) -> RunnerStatus: ...

    @property
    def line(self) -> int | None:
        """The step executing (or next to execute), None before the first."""

    @property
    def error(self) -> RunnerError | None:
        """Set when `status` is FAILED."""

    @property
    def waiting(self) -> bool:
        """The program sits in a WAIT (STATE's stop status shows 0x04)."""


class StepError(Exception):
    """A statement (EXEC or program step) refused with the controller's error number."""

    def __init__(self, number: int, message: str, *, level: ErrorLevel = ErrorLevel.LOW) -> None:
        super().__init__(message)
        self.number = number
        self.message = message
        self.level = level


@runtime_checkable
class StatementExecutor(Protocol):
    """Runs `EXEC<statement>`: returns when the statement is *accepted* (motion started,
    setting applied) [DOC S1 §5.2.16]; raises `StepError` when refused."""

    def execute(self, statement: str, now: float) -> None: ...


RunnerFactory = Callable[[], ProgramRunner]
"""Makes a fresh runner for a slot; the controller calls it on RUN/PRGLOAD."""


LINE_WALK_SECONDS = 0.05
"""How long `LineWalker` spends on each step (no interpreter: no real timing)."""


class LineWalker:
    """Placeholder runner: walks the steps in order, one per `LINE_WALK_SECONDS`, no motion.

    >>> w = LineWalker()
    >>> w.load("10 MOV P1\\n20 END\\n", {})
    >>> w.start(0.0, cycle=True); w.advance(0.06); (w.status.value, w.line)
    ('running', 20)
    >>> w.advance(1.0); w.status.value
    'finished'
    """

    def __init__(self) -> None:
        self._lines: list[int] = []
        self._status = RunnerStatus.IDLE
        self._index = 0
        self._since = 0.0
        self._cycle = True

    def load(self, text: str, positions: Mapping[str, str]) -> None:
        self._lines = []
        for raw in text.splitlines():
            head = raw.strip().split(" ", 1)[0]
            if head.isdigit():
                self._lines.append(int(head))
        self._lines.sort()
        self.reset()

    def start(self, now: float, *, cycle: bool) -> None:
        self._cycle = cycle
        self._index = 0
        self._since = now
        self._status = RunnerStatus.RUNNING if self._lines else RunnerStatus.FINISHED

    def resume(self, now: float) -> None:
        if self._status is RunnerStatus.PAUSED:
            self._since = now
            self._status = RunnerStatus.RUNNING

    def pause(self, now: float) -> None:
        if self._status is RunnerStatus.RUNNING:
            self.advance(now)
            self._status = RunnerStatus.PAUSED

    def reset(self) -> None:
        self._index = 0
        self._status = RunnerStatus.IDLE

    def advance(self, now: float) -> None:
        while self._status is RunnerStatus.RUNNING and now - self._since >= LINE_WALK_SECONDS:
            self._since += LINE_WALK_SECONDS
            self._index += 1
            if self._index >= len(self._lines):
                if self._cycle:
                    self._index = 0
                    self._status = RunnerStatus.FINISHED
                else:
                    self._index = 0

    @property
    def status(self) -> RunnerStatus:
        return self._status

    @property
    def line(self) -> int | None:
        return self._lines[self._index] if self._lines else None

    @property
    def error(self) -> RunnerError | None:
        return None

    @property
    def waiting(self) -> bool:
        return False
