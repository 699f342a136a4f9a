"""Run a program "as fast as possible": a simulated clock that jumps to the next event.

Used by tests, previews and ``melfa sim --run``: the same interpreter and arm as the
real-time controller, but instead of waiting for a move or a DLY to end, the clock jumps
to that moment. A program that only computes (a loop with no motion) advances the clock
by `SLICE_S` per `advance` call, so `max_time` bounds every run.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from melfa.sim.arm import SimulatedArm
from melfa.sim.interp.armport import ArmPort
from melfa.sim.interp.interpreter import Interpreter
from melfa.sim.interp.io import IOState
from melfa.sim.runner import RunnerStatus

SLICE_S = 0.01
"""Simulated time charged to one full statement budget (a controller tick) [GUESS]."""

DEFAULT_MAX_TIME_S = 3600.0


def run_fast(
    interp: Interpreter,
    *,
    start: float | None = None,
    max_time: float = DEFAULT_MAX_TIME_S,
) -> float:
    """Advance a started program until it ends, fails, pauses or `max_time` passes.

    Returns the simulated time reached.
    """
    t = interp.now if start is None else start
    limit = t + max_time
    while interp.status is RunnerStatus.RUNNING:
        interp.advance(t)
        if interp.status is not RunnerStatus.RUNNING:
            break
        nxt = interp.next_event_time()
        # The program's clock runs ahead of `t` by the steps it ran (STEP_TIME_S each).
        t = nxt if nxt is not None and nxt > t else max(t, interp.now) + SLICE_S
        if t > limit:
            break
    return interp.now


@dataclass(slots=True)
class Run:
    """A program run with no robot: the interpreter, its arm and the time reached."""

    interp: Interpreter
    arm: SimulatedArm
    end_time: float


def simulate(
    text: str,
    points: Mapping[str, str] | Iterable[str] = (),
    *,
    arm: SimulatedArm | None = None,
    io: IOState | None = None,
    max_time: float = DEFAULT_MAX_TIME_S,
) -> Run:
    """Load and run `text` from its first line on a fresh simulated RV-6S, fast.

    >>> run = simulate("10 M1 = 6 * 7\\n20 END\\n")
    >>> run.interp.state.vars["M1"], run.interp.status.value
    (42, 'finished')
    """
    arm = arm if arm is not None else SimulatedArm()
    interp = Interpreter(ArmPort(arm), io)
    interp.load(text, points)
    interp.start(0.0, cycle=True)
    end = run_fast(interp, max_time=max_time)
    return Run(interp, arm, end)
