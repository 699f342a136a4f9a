"""A `CellWorld` wired to a debugger's run: the hand's events, the outputs and the sensor
inputs of one simulated RV-6S (pre-flight and the IDE's simulator both use it).

`CellRun` listens to the arm's hand events and the outputs, and sets the sensors' inputs
whenever the program reads one (`IOState.before_read`). Times given to the
world are the interpreter's; `HandAction.time` is seconds since the run began.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable

from melfa.kin.pose import FloatArray
from melfa.kin.solver import fk_matrix
from melfa.sim.arm import SimulatedArm
from melfa.sim.debug.cell import Cell
from melfa.sim.debug.cell_world import CellWorld, HandAction, PartState
from melfa.sim.debug.engine import Debugger
from melfa.sim.interp.io import IOState
from melfa.sim.trajectory import HandEvent, HandState, MoveEvent


class CellRun:
    """The parts of `cell` following one arm's run (attach once; `reset` at each run, or
    `follow` a debugger, which resets it whenever a run starts)."""

    def __init__(
        self,
        cell: Cell,
        arm: SimulatedArm,
        io: IOState,
        *,
        now: Callable[[], float],
        line_of: Callable[[int | None], int | None],
    ) -> None:
        self.cell = cell
        self.arm = arm
        self.io = io
        self._now = now
        self._line_of = line_of
        self.origin = now()
        self.world = CellWorld(cell)
        self._debugger: Debugger | None = None
        arm.recorder.listeners.append(self._on_event)
        io.listeners.append(self._on_io)
        io.before_read = self.sense

    @classmethod
    def follow(cls, cell: Cell, debugger: Debugger) -> CellRun:
        """The cell's parts following `debugger`'s runs (its I/O must be a `CellIO`)."""
        run = cls(
            cell,
            debugger.arm,
            debugger.io,
            now=lambda: debugger.interp.now,
            line_of=debugger.line_of_step,
        )
        debugger.on_start.append(run.reset)
        run._debugger = debugger
        return run

    def detach(self) -> None:
        """Stop following the arm and its I/O (the I/O may outlive the run)."""
        with contextlib.suppress(ValueError):
            self.arm.recorder.listeners.remove(self._on_event)
        with contextlib.suppress(ValueError):
            self.io.listeners.remove(self._on_io)
        if self.io.before_read == self.sense:
            self.io.before_read = None
        if self._debugger is not None:
            with contextlib.suppress(ValueError):
                self._debugger.on_start.remove(self.reset)

    def reset(self) -> None:
        """A new run: the parts back where the cell puts them."""
        self.origin = self._now()
        self.world = CellWorld(self.cell)
        for bit, value in self.io.outputs().items():
            self.world.set_output(0.0, bit, value)

    def _time(self) -> float:
        """Seconds since the run began (the world's clock)."""
        return self._now() - self.origin

    def flange(self) -> FloatArray:
        """The flange's transform in the world frame (BASE applied, not TOOL)."""
        return fk_matrix(self.arm.joints, None, self.arm.base)

    def sense(self) -> None:
        """Conveyors up to now, then the sensors' inputs."""
        self.world.advance(self._time())
        for bit, value in self.world.inputs(self.flange()).items():
            self.io.set_input(bit, value)

    def parts(self) -> list[PartState]:
        """Every part now (a held one where the arm holds it)."""
        self.world.advance(self._time())
        return self.world.parts(self.flange())

    @property
    def actions(self) -> list[HandAction]:
        return self.world.actions

    def _on_event(self, event: HandEvent | MoveEvent) -> None:
        if not isinstance(event, HandEvent) or event.hand != self.cell.gripper.hand:
            return
        p = self.arm.pose
        pose = (p.x, p.y, p.z, p.a, p.b, p.c)
        line = self._line_of(event.line)
        world = self.world
        act = world.open if event.state is HandState.OPEN else world.close
        act(event.time - self.origin, self.flange(), pose, line)

    def _on_io(self, kind: str, bit: int, value: int) -> None:
        if kind == "out":
            self.world.set_output(self._time(), bit, value)
