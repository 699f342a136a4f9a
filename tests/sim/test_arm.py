"""The simulated arm: injected time, refusals with controller numbers, stop, hands, jog."""

import pytest

from melfa.kin import HOME, JOINT_MAX_SPEED, Joints, Pose, fk
from melfa.sim.arm import (
    JOG_WATCHDOG_S,
    JogInch,
    JogMode,
    SimulatedArm,
    directions_from_masks,
)
from melfa.sim.arm_errors import (
    ERR_BUSY,
    ERR_ILLEGAL_POSITION,
    ERR_JOINT_LIMIT,
    ERR_OUT_OF_RANGE,
    ERR_SERVO_OFF,
    ArmBusy,
    IllegalPosition,
    JogRefused,
    JointLimitError,
    OutOfRange,
    ServoOff,
)
from melfa.sim.motion import ACCEL_TIME_S
from melfa.sim.plans import MoveKind
from melfa.sim.trajectory import (
    HandEvent,
    HandState,
    MoveEvent,
    TrajectoryRecorder,
)

HOME_POSE = fk(HOME)


def at(x: float, y: float, z: float) -> Pose:
    return Pose(x, y, z, HOME_POSE.a, HOME_POSE.b, HOME_POSE.c)


@pytest.fixture
def arm() -> SimulatedArm:
    return SimulatedArm(servo_on=True)


def test_starts_at_home_with_the_servo_off() -> None:
    fresh = SimulatedArm()
    assert fresh.joints == HOME
    assert not fresh.servo_on
    assert fresh.pose.xyz == pytest.approx((400, 0, 645))
    assert (fresh.pose.fl1, fresh.pose.fl2) == (7, 0)


def test_mov_takes_the_slowest_joints_time(arm: SimulatedArm) -> None:
    target = Joints(0, 0, 90, 0, 90, 330)  # J6: 0.5 s at 660 deg/s
    plan = arm.move_joint(target, now=10.0)
    assert plan.duration == pytest.approx(330 / JOINT_MAX_SPEED[5] + ACCEL_TIME_S)
    assert arm.motion_end() == pytest.approx(10.0 + plan.duration)
    assert arm.is_moving(10.3)
    assert 0 < arm.joints.j6 < 330
    assert not arm.is_moving(10.0 + plan.duration)
    assert arm.joints == target
    assert arm.motion_end() is None


def test_ovrd_halves_speed_and_doubles_the_cruise(arm: SimulatedArm) -> None:
    target = Joints(0, 0, 90, 0, 90, 330)
    full = arm.move_joint(target, 0.0).duration
    arm.advance(100.0)
    arm.set_speeds(ovrd=50)
    half = arm.move_joint(HOME, 100.0).duration
    assert half - ACCEL_TIME_S == pytest.approx(2 * (full - ACCEL_TIME_S))
    arm.advance(200.0)
    arm.reset_speeds()
    assert arm.speeds.ovrd == 100
    assert arm.move_joint(target, 200.0).duration == pytest.approx(full)


def test_op_override_survives_program_reset(arm: SimulatedArm) -> None:
    arm.set_op_override(25)
    arm.set_speeds(jovrd=50, spd=100, accel=(50, 80))
    arm.reset_speeds()
    assert arm.speeds.op_override == 25
    assert (arm.speeds.jovrd, arm.speeds.accel, arm.speeds.decel) == (100, 100, 100)


@pytest.mark.parametrize("bad", [0, 101, -5])
def test_override_outside_its_range_is_a_caller_error(arm: SimulatedArm, bad: float) -> None:
    with pytest.raises(ValueError, match="above 0 and at most 100"):
        arm.set_speeds(ovrd=bad)
    with pytest.raises(ValueError, match="1–100"):
        arm.set_op_override(bad)


def test_a_program_override_below_1_percent_is_valid(arm: SimulatedArm) -> None:
    arm.set_speeds(ovrd=0.5, jovrd=0.1)  # resolution 0.1 % [S1 OVRD]
    assert (arm.speeds.ovrd, arm.speeds.jovrd) == (0.5, 0.1)


def test_servo_off_refuses_moves_with_2000() -> None:
    arm = SimulatedArm()
    with pytest.raises(ServoOff) as err:
        arm.move_joint(Joints(10, 0, 90, 0, 90, 0), 0.0)
    assert err.value.number == ERR_SERVO_OFF == 2000
    assert err.value.code == "L2000"
    with pytest.raises(ServoOff):
        arm.jog(JogMode.JOINT, (1,), 0.0)
    assert arm.joints == HOME


def test_joint_limit_target_raises_2160_with_the_joint(arm: SimulatedArm) -> None:
    with pytest.raises(JointLimitError) as err:
        arm.move_joint(Joints(0, 0, 90, 0, 130, 0), 0.0)
    assert err.value.number == ERR_JOINT_LIMIT == 2160
    assert err.value.code == "H2160"
    assert err.value.joint == 5
    assert err.value.value == 130
    assert not arm.is_moving(0.0)


def test_interference_target_raises_2160(arm: SimulatedArm) -> None:
    with pytest.raises(JointLimitError) as err:
        arm.move_joint(Joints(0, -60, 60, 0, 90, 0), 0.0)
    assert err.value.joint is None


def test_unreachable_pose_raises_2600(arm: SimulatedArm) -> None:
    with pytest.raises(OutOfRange) as err:
        arm.move_linear(at(1500, 0, 600), 0.0)
    assert err.value.number == ERR_OUT_OF_RANGE
    with pytest.raises(OutOfRange):
        arm.move_joint(at(1500, 0, 600), 0.0)


def test_collinear_arc_raises_2800(arm: SimulatedArm) -> None:
    with pytest.raises(IllegalPosition) as err:
        arm.move_arc(HOME_POSE, at(450, 0, 645), at(500, 0, 645), 0.0)
    assert err.value.number == ERR_ILLEGAL_POSITION


def test_a_move_while_moving_is_busy(arm: SimulatedArm) -> None:
    arm.move_joint(Joints(90, 0, 90, 0, 90, 0), 0.0)
    with pytest.raises(ArmBusy) as err:
        arm.move_joint(HOME, 0.1)
    assert err.value.number == ERR_BUSY
    with pytest.raises(JogRefused):
        arm.jog(JogMode.JOINT, (1,), 0.1)


def test_immediate_stop_freezes_the_joints(arm: SimulatedArm) -> None:
    arm.move_joint(Joints(150, 0, 90, 0, 90, 0), 0.0)
    arm.stop(0.3, immediate=True)
    frozen = arm.joints
    assert 0 < frozen.j1 < 150
    assert not arm.is_moving(5.0)
    assert arm.joints == frozen


def test_stop_decelerates_then_holds(arm: SimulatedArm) -> None:
    plan = arm.move_joint(Joints(150, 0, 90, 0, 90, 0), 0.0)
    arm.stop(0.3)
    at_stop = arm.joints.j1
    end = arm.motion_end()
    assert end is not None
    assert 0.3 < end <= 0.3 + ACCEL_TIME_S + 1e-9 < plan.duration
    arm.advance(end)
    stopped = arm.joints
    assert at_stop < stopped.j1 < 150
    arm.advance(end + 10)
    assert arm.joints == stopped
    assert not arm.is_moving()


def test_servo_off_mid_move_stops_at_once(arm: SimulatedArm) -> None:
    arm.move_joint(Joints(150, 0, 90, 0, 90, 0), 0.0)
    arm.set_servo(False, 0.2)
    held = arm.joints
    arm.advance(3.0)
    assert arm.joints == held
    assert not arm.servo_on


def test_mvs_and_mvc_through_the_arm(arm: SimulatedArm) -> None:
    plan = arm.move_linear(at(400, 100, 600), 0.0)
    arm.advance(plan.duration)
    assert arm.pose.xyz == pytest.approx((400, 100, 600), abs=1e-6)
    now = plan.duration
    circle = arm.move_circle(arm.pose, at(450, 150, 600), at(500, 100, 600), now)
    arm.advance(now + circle.duration)
    assert arm.pose.xyz == pytest.approx((400, 100, 600), abs=1e-6)


def test_mvs_offset_and_close_distance(arm: SimulatedArm) -> None:
    plan = arm.move_linear_offset(-30, 0.0)
    arm.advance(plan.duration)
    assert arm.pose.z == pytest.approx(675)
    plan2 = arm.move_joint(at(400, 0, 500), 5.0, close=-50)
    arm.advance(5.0 + plan2.duration)
    assert arm.pose.z == pytest.approx(550)


def test_tool_changes_the_reported_pose(arm: SimulatedArm) -> None:
    arm.set_tool(Pose(0, 0, 100, 0, 0, 0))
    assert arm.pose.z == pytest.approx(545)
    assert arm.flange_pose.z == pytest.approx(645)
    plan = arm.move_linear(at(400, 0, 500), 0.0)
    arm.advance(plan.duration)
    assert arm.pose.z == pytest.approx(500)
    assert arm.flange_pose.z == pytest.approx(600)


def test_hands_are_recorded(arm: SimulatedArm) -> None:
    assert arm.hand_open(1) is None
    arm.set_line(20)
    arm.set_hand(1, True, 0.5)
    arm.set_hand(2, False, 0.6)
    assert arm.hand_open(1) is True
    assert arm.hand_open(2) is False
    assert arm.hands[:3] == (HandState.OPEN, HandState.CLOSED, None)
    assert arm.recorder.hand_events == [
        HandEvent(0.5, 1, HandState.OPEN, 20),
        HandEvent(0.6, 2, HandState.CLOSED, 20),
    ]
    with pytest.raises(ValueError, match="1–8"):
        arm.set_hand(9, True, 1.0)


def test_recorder_keeps_moves_and_samples_with_the_line(arm: SimulatedArm) -> None:
    arm.set_line(40)
    plan = arm.move_joint(Joints(30, 0, 90, 0, 90, 0), 1.0)
    for k in range(1, 6):
        arm.advance(1.0 + k * plan.duration / 5)
    moves = arm.recorder.moves
    assert len(moves) == 1
    assert isinstance(moves[0], MoveEvent)
    assert (moves[0].kind, moves[0].time, moves[0].line) == (MoveKind.JOINT, 1.0, 40)
    samples = arm.recorder.samples
    assert [s.time for s in samples] == sorted(s.time for s in samples)
    assert samples[-1].joints == Joints(30, 0, 90, 0, 90, 0)
    assert all(s.line == 40 for s in samples)
    assert arm.record(99.0, line=50).line == 50


def test_recorder_is_bounded() -> None:
    rec = TrajectoryRecorder(max_samples=5, max_events=2)
    arm = SimulatedArm(servo_on=True, recorder=rec)
    for k in range(20):
        arm.record(float(k))
        arm.set_hand(1, k % 2 == 0, float(k))
    assert len(rec.samples) == 5
    assert len(rec.events) == 2
    assert rec.samples[-1].time == 19.0


def test_fast_mode_jumps_to_the_end(arm: SimulatedArm) -> None:
    now = 0.0
    for target in (Joints(30, 10, 80, 0, 60, 0), Joints(-30, 0, 90, 10, 90, 40), HOME):
        arm.move_joint(target, now)
        end = arm.motion_end()
        assert end is not None
        now = end
        arm.advance(now)
        assert arm.joints == target


def test_joint_jog_runs_until_the_watchdog(arm: SimulatedArm) -> None:
    arm.set_op_override(50)
    arm.jog(JogMode.JOINT, directions_from_masks(0, 0x01), 0.0)
    assert arm.is_moving(0.1)
    arm.jog(JogMode.JOINT, directions_from_masks(0, 0x01), 0.1)  # resent within 140 ms
    arm.advance(1.0)
    assert not arm.is_moving()
    speed = JOINT_MAX_SPEED[0] * 0.1 * 0.5
    assert arm.joints.j1 == pytest.approx(speed * (0.1 + JOG_WATCHDOG_S))


def test_jog_stop_and_zero_masks_stop(arm: SimulatedArm) -> None:
    arm.jog(JogMode.XYZ, (0, 0, 1), 0.0)
    arm.jog_stop(0.1)
    z = arm.pose.z
    assert z == pytest.approx(645 + 250 * 0.1)
    arm.advance(1.0)
    assert arm.pose.z == pytest.approx(z)
    arm.jog(JogMode.XYZ, (1,), 2.0)
    arm.jog(JogMode.XYZ, (0, 0, 0), 2.05)
    assert not arm.is_moving(3.0)


def test_cartesian_jog_into_the_range_limit_stops_with_a_fault(arm: SimulatedArm) -> None:
    t = 0.0
    while t < 10 and arm.fault is None:
        arm.jog(JogMode.XYZ, (1,), t)
        t += 0.1
        arm.advance(t)
    assert isinstance(arm.fault, OutOfRange | JointLimitError)
    assert not arm.is_moving()
    arm.clear_fault()
    assert arm.fault is None


def test_inching_moves_one_step(arm: SimulatedArm) -> None:
    arm.jog(JogMode.XYZ, (0, -1), 0.0, inch=JogInch.HIGH)
    end = arm.motion_end()
    assert end is not None
    arm.advance(end)
    assert arm.pose.y == pytest.approx(-1.0)
    j6 = arm.joints.j6
    arm.jog(JogMode.JOINT, (0, 0, 0, 0, 0, 1), end, inch=JogInch.LOW)
    arm.advance(end + 1)
    assert arm.joints.j6 == pytest.approx(j6 + 0.1)


def test_unsupported_jog_mode_is_refused(arm: SimulatedArm) -> None:
    with pytest.raises(JogRefused):
        arm.jog(JogMode.CYLINDRICAL, (1,), 0.0)


def test_to_joints_maps_kinematics_errors(arm: SimulatedArm) -> None:
    q = arm.to_joints(fk((10, 20, 100, 30, 40, 50)))
    assert q == pytest.approx((10, 20, 100, 30, 40, 50))
    with pytest.raises(OutOfRange):
        arm.to_joints(at(2000, 0, 0))
    assert arm.to_pose(HOME).xyz == pytest.approx((400, 0, 645))
