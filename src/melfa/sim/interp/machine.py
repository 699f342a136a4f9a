"""What compiled statements may ask of the interpreter that runs them: `Machine`.

The statement compilers are written against this protocol, not against `Interpreter`, so
the package has no import cycle: state lives in `state.ProgramState`, the arm behind
`robot.RobotPort`, and the few operations that need both (start a move, SKIP, HLT during a
move, END) are here. `interpreter.Interpreter` implements it.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Protocol

from melfa.sim.interp.builtins import Rnd
from melfa.sim.interp.io import IOState
from melfa.sim.interp.robot import RobotPort
from melfa.sim.interp.state import ProgramState
from melfa.sim.interp.sysvars import SystemVariables

Watch = tuple[Callable[[], bool], Callable[[], None]]
"""A WTHIF: (condition, action) checked while a move runs."""


class Machine(Protocol):
    """The interpreter as the compiled statements see it."""

    @property
    def state(self) -> ProgramState: ...

    @property
    def robot(self) -> RobotPort: ...

    @property
    def io(self) -> IOState: ...

    @property
    def sysvars(self) -> SystemVariables: ...

    @property
    def rnd(self) -> Rnd: ...

    @property
    def feed(self) -> dict[int, deque[str]]:
        """Lines scripted for ``INPUT #n`` by file number."""

    def start_motion(self, move: Callable[[float], float], watch: Watch | None = None) -> None:
        """Begin a move (`move(now)` returns its end time) and block until it ends."""

    def skip_motion(self) -> None:
        """SKIP: stop the move and go on with the next line."""

    def halt(self, now: float) -> None:
        """STOP/HLT during a move: the arm decelerates, RUN redoes the move."""

    def end(self) -> None:
        """END: speeds back to defaults; finish (or start over when cycling)."""
