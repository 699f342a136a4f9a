"""`DebugSession`: the debug engine (`melfa.sim.debug.engine.Debugger`) run for one user
beside their private simulator, with a timer that moves it and events that show it.

The engine is pure and clockless; this module gives it a clock, polls it (`POLL_S`) in a
worker thread so an instant-speed run never blocks the event loop, serialises commands with
the polls (one lock), and publishes `DebugUpdate` events on the private simulator's bus: the
IDE's socket for "My simulator" gets them with the robot's state. While the program runs an
update goes out at most every `UPDATE_S` (location, time, the arm's joints and pose and
where the cell's parts are, for the 3D view); at every stop one goes out at once, with the
variables.

The debugged program runs on an arm of its own that starts where the simulator's arm
stands: the debugger's simulated time stands still while paused and runs ×N or instantly on
request, which the controller's real-time clock cannot follow.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, TypeVar

from melfa.service.events import Actor, Event
from melfa.service.simulator import PrivateSimulator
from melfa.sim.arm import SimulatedArm
from melfa.sim.debug.cell import Cell
from melfa.sim.debug.cell_run import CellRun
from melfa.sim.debug.engine import DebugError, Debugger, RunState, Speed, Stop
from melfa.sim.interp.io import IOState
from melfa.sim.interp.start import RunStart
from melfa.sim.machine import SimArm

T = TypeVar("T")

POLL_S = 0.03
"""How often a running program is moved on (the engine keeps its own timing between)."""
_SESSION_IDS = itertools.count(1)
AS_THE_SIMULATOR_IS = RunStart(servo_on=None)
"""A debug run's default start: the simulator's arm as it is (joints, servo, hands)."""
UPDATE_S = 0.1
"""Most often a running program's location and arm are published (stops go at once)."""


@dataclass(frozen=True, kw_only=True)
class DebugUpdate(Event):
    """The debugger's state for the IDE (`status` is the engine's `Status.to_json()`)."""

    NAME: ClassVar[str] = "debug"
    session: int
    """Which debug session (a new one starts its `seq` again)."""
    seq: int
    """Grows with every change: a view shows the highest it has seen (a command's reply and
    the socket's message may cross)."""
    status: dict[str, Any]
    joints: tuple[float, ...] | None = None
    pose: tuple[float, ...] | None = None
    variables: list[dict[str, Any]] | None = None
    """Sent with every stop (the values the last step changed are marked)."""
    parts: list[dict[str, Any]] | None = None
    """Where each part of the cell is (`cell_world.PartState.to_json()`), when it has any."""
    ended: bool = False
    """The session was closed: the view goes back to the simulator's own state."""


def _arm_like(simulator: PrivateSimulator, start: RunStart) -> SimulatedArm:
    """A fresh arm as ``start`` asks; what it leaves open is as the simulator's arm is
    (where it stands, servo, hands, override)."""

    def read(controller: Any, now: float) -> SimulatedArm:
        arm = controller.arm
        return start.arm(arm.arm if isinstance(arm, SimArm) else None)

    return simulator.call(read)


class DebugSession:
    """One user's program under the debugger. Make it with `open`, `close` it when done."""

    def __init__(
        self,
        simulator: PrivateSimulator,
        debugger: Debugger,
        owner: Actor,
        *,
        clock: Callable[[], float] = time.monotonic,
        cell: Cell | None = None,
    ) -> None:
        self.simulator = simulator
        self.debugger = debugger
        self.cell = CellRun.follow(cell, debugger) if cell is not None and cell.parts else None
        self.owner = owner
        self.program = debugger.text
        self._clock = clock
        self._lock = threading.Lock()
        self._task: asyncio.Task[None] | None = None
        self._last_update = float("-inf")
        self._closed = False
        self._seq = 0
        self.id = next(_SESSION_IDS)

    @classmethod
    async def open(
        cls,
        simulator: PrivateSimulator,
        owner: Actor,
        program: str,
        points: str,
        *,
        speed: Speed | None = None,
        start: RunStart = AS_THE_SIMULATOR_IS,
        clock: Callable[[], float] = time.monotonic,
        cell: Cell | None = None,
    ) -> DebugSession:
        """Load ``program`` and ``points`` (`DebugError` in the user's words when they
        cannot run at all) on an arm as ``start`` says, by default where the simulator's
        stands; the `cell`'s parts follow the run (carried, dropped, on conveyors) and go
        out with every update."""
        arm = _arm_like(simulator, start)
        debugger = await asyncio.to_thread(
            Debugger,
            program,
            points,
            clock=clock,
            speed=speed or Speed(1.0),
            arm=arm,
            io=_io_of(simulator),
        )
        start.apply(debugger.interp)
        session = cls(simulator, debugger, owner, clock=clock, cell=cell)
        session._task = asyncio.create_task(session._pump(), name=f"debug-{owner.user}")
        session.publish(with_variables=True)
        return session

    @property
    def closed(self) -> bool:
        return self._closed

    async def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        if self._task is not None:
            self._task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._task
        if self.cell is not None:
            with self._lock:
                self.cell.detach()
        with contextlib.suppress(Exception):
            self.publish(ended=True)

    async def call(self, fn: Callable[[Debugger], T]) -> T:
        """Run one engine command (serialised with the polls, off the event loop); the
        new state is published at once."""
        if self._closed:
            raise DebugError("the debug session has ended: start it again")
        result = await asyncio.to_thread(self._locked, fn)
        self.publish(with_variables=True)
        return result

    def _locked(self, fn: Callable[[Debugger], T]) -> T:
        with self._lock:
            return fn(self.debugger)

    def status(self) -> dict[str, Any]:
        with self._lock:
            return self.debugger.status().to_json()

    def snapshot(self) -> tuple[int, dict[str, Any], list[dict[str, Any]]]:
        """(seq, status, variables) read together."""
        with self._lock:
            d = self.debugger
            return self._seq, d.status().to_json(), [v.to_json() for v in d.variables()]

    def variables(self) -> list[dict[str, Any]]:
        with self._lock:
            return [v.to_json() for v in self.debugger.variables()]

    def update(self, *, with_variables: bool = False, ended: bool = False) -> DebugUpdate:
        with self._lock:
            d = self.debugger
            arm = d.arm
            self._seq += 1
            return DebugUpdate(
                actor=self.owner,
                session=self.id,
                seq=self._seq,
                status=d.status().to_json(),
                joints=tuple(arm.joints),
                pose=_pose(arm),
                variables=[v.to_json() for v in d.variables()] if with_variables else None,
                parts=[p.to_json() for p in self.cell.parts()] if self.cell else None,
                ended=ended,
            )

    def publish(self, *, with_variables: bool = False, ended: bool = False) -> None:
        self._last_update = self._clock()
        self.simulator.service.publish(self.update(with_variables=with_variables, ended=ended))

    async def _pump(self) -> None:
        """Move a running program on; publish what happened."""
        while True:
            await asyncio.sleep(POLL_S)
            if self.debugger.state is not RunState.RUNNING:
                continue
            stop: Stop | None = await asyncio.to_thread(self._locked, lambda d: d.poll())
            if stop is not None:
                self.publish(with_variables=True)
            elif self._clock() - self._last_update >= UPDATE_S:
                self.publish()


def _io_of(simulator: PrivateSimulator) -> IOState:
    """The simulator's I/O signals: inputs a student set stay set in the debugger."""
    io: IOState = simulator.call(lambda controller, now: controller.io)
    return io


def _pose(arm: SimulatedArm) -> tuple[float, ...]:
    pose = arm.pose
    return (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)


__all__ = ["POLL_S", "UPDATE_S", "DebugSession", "DebugUpdate"]
