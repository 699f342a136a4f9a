"""The poll plan's reads against the virtual controller, on a clock the test moves: which
pose the state shows for a still arm."""

from __future__ import annotations

from melfa.robot import Robot
from melfa.service import ServiceConfig
from melfa.service.polling import JointsRead, PollCommand, Poller, PoseRead
from melfa.sim import VirtualController, open_sim_link


class Clock:
    def __init__(self) -> None:
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_a_pose_measured_as_the_arm_stopped_stands_while_it_stays_still() -> None:
    """The last JPOSF of a move (the joints changed, so "moving") and then a PPOSF at rest
    — a poll cycle planned before the move resumes after it — and then the same joints
    again: the measured pose stands. It used to be replaced by the pose computed from the
    2-decimal joints, ~0.07 mm away: a still arm's pose flickered."""
    clock = Clock()
    robot = Robot(open_sim_link(controller=VirtualController(), clock=clock))
    poller = Poller(ServiceConfig())
    poller.read(robot, PollCommand.JOINTS)
    poller.read(robot, PollCommand.POSE)  # at rest: the tool offset is learnt
    assert poller.tool_offset is not None

    robot.exec("SERVO ON")
    robot.exec("MVS P_CURR+(20,0,-30,0,0,0)")
    clock.t += 30.0  # the move is over
    last = poller.read(robot, PollCommand.JOINTS)
    assert isinstance(last, JointsRead) and last.moving  # the joints changed since
    measured = poller.read(robot, PollCommand.POSE)
    assert isinstance(measured, PoseRead)

    again = poller.read(robot, PollCommand.JOINTS)
    assert isinstance(again, JointsRead)
    assert again.joints == last.joints and not again.moving
    assert again.pose is None  # the measured pose is not replaced
