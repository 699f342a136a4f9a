"""A controller's simulated arm keeps a bounded trajectory: a private simulator that runs
a looping program for hours does not grow the server."""

from __future__ import annotations

from melfa.sim import VirtualController
from melfa.sim.machine import CONTROLLER_EVENTS, CONTROLLER_SAMPLES
from melfa.sim.trajectory import HandEvent, HandState
from tests.sim.test_controller_programs import sim_arm


def test_the_arms_record_is_bounded() -> None:
    arm = sim_arm(VirtualController())
    for step in range(5 * CONTROLLER_SAMPLES):
        arm.record(step * 0.05)
        arm.recorder.add_event(HandEvent(step * 0.05, 1, HandState.OPEN, None))
    assert len(arm.recorder.samples) == CONTROLLER_SAMPLES
    assert len(arm.recorder.events) == CONTROLLER_EVENTS
    assert arm.recorder.samples[-1].time == (5 * CONTROLLER_SAMPLES - 1) * 0.05
