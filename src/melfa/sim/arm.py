"""The simulated RV-6S arm: joints, servo, hands, speed settings, TOOL/BASE, motion in time.

Time is injected: every call that can change the state takes ``now`` (seconds of the
caller's clock, real or simulated) and nothing here reads a clock. A move builds a plan
(`melfa.sim.motion`), checked before the arm starts, and `advance(now)` moves the joints
along it. "As fast as possible" callers jump their clock to `motion_end()`.

Both the virtual controller's EXEC and the interpreter's RUN drive one `SimulatedArm`.
Its refusals are `melfa.sim.arm_errors.ArmError`s; what it did is kept by a
`melfa.sim.trajectory.TrajectoryRecorder`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from melfa.kin import (
    DEFAULT_INTERFERENCE,
    HOME,
    Interference,
    Joints,
    KinematicsError,
    Pose,
    fk,
    ik,
    pose_mul,
)
from melfa.protocol.jog import JOG_WATCHDOG_S, JogInch, JogMode
from melfa.protocol.limits import (
    HANDS,
    OVERRIDE_PERCENT,
    PROGRAM_OVERRIDE_TEXT,
    is_program_override,
    span_text,
)
from melfa.sim import motion
from melfa.sim.arm_errors import (
    ArmBusy,
    ArmError,
    JogRefused,
    ServoOff,
    from_kinematics,
)
from melfa.sim.motion import Speeds
from melfa.sim.plans import Frames, Plan
from melfa.sim.timing import Profile
from melfa.sim.trajectory import (
    HandEvent,
    HandState,
    MoveEvent,
    TrajectoryRecorder,
    TrajectorySample,
)

__all__ = [
    "JOG_WATCHDOG_S",
    "JogInch",
    "JogMode",
    "SimulatedArm",
    "directions_from_masks",
]


JOG_STEP_S = 0.02
"""Integration step of continuous jog (Cartesian jog solves IK at each step)."""
INCH_HIGH = 1.0
"""[GUESS] inching step "high": mm for XYZ/TOOL axes, degrees for joints and A/B/C."""
INCH_LOW = 0.1
"""[GUESS] inching step "low"."""
OP_OVERRIDE_DEFAULT = 100.0
"""[GUESS] the OP override after power-on (the real one is whatever the panel was left at)."""


# --- jog ---------------------------------------------------------------------------------


def directions_from_masks(negative: int, positive: int) -> tuple[int, ...]:
    """Per-axis -1/0/+1 from the JOG command's axis masks (bit 0 = X/J1 ... bit 7 = L2/J8).

    >>> directions_from_masks(0x01, 0x04)
    (-1, 0, 1, 0, 0, 0, 0, 0)
    """
    return tuple(((positive >> i) & 1) - ((negative >> i) & 1) for i in range(8))


@dataclass(slots=True)
class _Jog:
    mode: JogMode
    directions: tuple[int, ...]
    last_command: float


# --- the arm -------------------------------------------------------------------------------


class SimulatedArm:
    """The simulated RV-6S. All times are seconds of the caller's clock.

    >>> arm = SimulatedArm(servo_on=True)
    >>> plan = arm.move_joint(Joints(10, 0, 90, 0, 90, 0), now=0.0)
    >>> arm.is_moving(0.1), arm.is_moving(plan.duration)
    (True, False)
    >>> arm.joints
    Joints(j1=10.0, j2=0.0, j3=90.0, j4=0.0, j5=90.0, j6=0.0)
    """

    def __init__(
        self,
        joints: Sequence[float] = HOME,
        *,
        now: float = 0.0,
        servo_on: bool = False,
        recorder: TrajectoryRecorder | None = None,
        interference: Interference = DEFAULT_INTERFERENCE,
        profile: Profile = Profile.TRAPEZOID,
        jog_watchdog_s: float = JOG_WATCHDOG_S,
    ) -> None:
        self._joints = Joints.of(joints)
        self.jog_watchdog_s = jog_watchdog_s
        """A jog not renewed within this long stops (the controller's, `SimConfig`'s)."""
        self._time = now
        self._servo = servo_on
        self._hands: list[HandState | None] = [None] * len(HANDS)
        self._op_override = OP_OVERRIDE_DEFAULT
        self._profile = profile
        self._speeds = Speeds(op_override=self._op_override, profile=profile)
        self._interference = interference
        self._tool: Pose | None = None
        self._base: Pose | None = None
        self._plan: Plan | None = None
        self._plan_start = now
        self._plan_end = now
        self._jog: _Jog | None = None
        self._line: int | None = None
        self.recorder = recorder if recorder is not None else TrajectoryRecorder()
        self.fault: ArmError | None = None
        """Set when a continuous jog ran into a limit (it stopped there); the controller
        reads it, raises its alarm, and clears it with `clear_fault()`."""

    # --- state ------------------------------------------------------------------------

    @property
    def joints(self) -> Joints:
        """Joints (deg) as of the last `advance`."""
        return self._joints

    @property
    def pose(self) -> Pose:
        """TCP pose under the active TOOL and BASE, with structure flags (P_CURR)."""
        return fk(self._joints, self._tool, self._base)

    @property
    def flange_pose(self) -> Pose:
        return fk(self._joints)

    @property
    def servo_on(self) -> bool:
        return self._servo

    @property
    def time(self) -> float:
        """The latest time the arm was advanced to."""
        return self._time

    @property
    def frames(self) -> Frames:
        return Frames(self._tool, self._base, self._interference)

    @property
    def tool(self) -> Pose | None:
        return self._tool

    @property
    def base(self) -> Pose | None:
        return self._base

    @property
    def plan(self) -> Plan | None:
        """The running plan (None when still or jogging)."""
        return self._plan

    @property
    def line(self) -> int | None:
        return self._line

    def set_line(self, line: int | None) -> None:
        """The program line now executing, stamped on what the recorder keeps."""
        self._line = line

    def set_tool(self, tool: Pose | None) -> None:
        """TOOL: the TCP relative to the flange (None = flange)."""
        self._tool = tool

    def set_base(self, base: Pose | None) -> None:
        """BASE: the robot base frame as seen from the world frame (None = identity)."""
        self._base = base

    # --- speed settings ---------------------------------------------------------------

    @property
    def speeds(self) -> Speeds:
        return self._speeds

    @property
    def op_override(self) -> float:
        return self._op_override

    def set_op_override(self, percent: float) -> None:
        """OP (panel) override, `OVERRIDE_PERCENT` (the protocol's ``OVRD=``)."""
        _check_percent("OP override", percent)
        self._op_override = float(percent)
        self._speeds = replace(self._speeds, op_override=float(percent))

    def set_speeds(
        self,
        *,
        ovrd: float | None = None,
        jovrd: float | None = None,
        spd: float | None = None,
        accel: tuple[float, float] | None = None,
    ) -> None:
        """Program settings: OVRD and JOVRD (0 < % <= 100), SPD (mm/s, > 0), ACCEL (acc, dec %).

        Out-of-range values are the caller's mistake (`ValueError`); the interpreter
        validates program values and reports them with its own error numbers.
        """
        s = self._speeds
        if ovrd is not None:
            _check_program_percent("OVRD", ovrd)
            s = replace(s, ovrd=float(ovrd))
        if jovrd is not None:
            _check_program_percent("JOVRD", jovrd)
            s = replace(s, jovrd=float(jovrd))
        if spd is not None:
            if not spd > 0:
                raise ValueError(f"SPD must be > 0 mm/s, got {spd}")
            s = replace(s, spd=float(spd))
        if accel is not None:
            acc, dec = accel
            if not (acc > 0 and dec > 0):
                raise ValueError(f"ACCEL must be > 0 %, got {acc}, {dec}")
            s = replace(s, accel=float(acc), decel=float(dec))
        self._speeds = s

    def reset_speeds(self) -> None:
        """Program settings back to their defaults (END, program reset) [S1 END]."""
        self._speeds = Speeds(op_override=self._op_override, profile=self._profile)

    # --- servo and hands --------------------------------------------------------------

    def set_servo(self, on: bool, now: float) -> None:
        """Servo on/off; switching off while moving stops the arm where it is (brakes)."""
        self.advance(now)
        if not on:
            self._plan = None
            self._jog = None
        self._servo = on

    def set_hand(self, hand: int, open_: bool, now: float) -> None:
        """HOPEN/HCLOSE (a hand number in `HANDS`). Recorded as a hand event."""
        if hand not in HANDS:
            raise ValueError(f"hand number {hand} is outside {span_text(HANDS)}")
        self.advance(now)
        state = HandState.OPEN if open_ else HandState.CLOSED
        self._hands[hand - 1] = state
        self.recorder.add_event(HandEvent(now, hand, state, self._line))
        self._record(now)

    def hand_open(self, hand: int) -> bool | None:
        """True open, False closed, None never commanded since start."""
        state = self._hands[hand - 1]
        return None if state is None else state is HandState.OPEN

    @property
    def hands(self) -> tuple[HandState | None, ...]:
        return tuple(self._hands)

    # --- time --------------------------------------------------------------------------

    def advance(self, now: float) -> Joints:
        """Bring the joints up to `now` along the plan or jog. Earlier times are ignored."""
        if now < self._time:
            return self._joints
        moving = self._plan is not None or self._jog is not None
        if self._plan is not None:
            if now >= self._plan_end:  # absolute compare: exact for clocks jumped to the end
                self._joints = self._plan.end_joints
                self._plan = None
            else:
                self._joints = self._plan.sample(now - self._plan_start)
        if self._jog is not None:
            self._advance_jog(now)
        self._time = now
        if moving:
            self._record(now)
        return self._joints

    def is_moving(self, now: float | None = None) -> bool:
        """Whether a plan or jog is still running (after advancing to `now` when given)."""
        if now is not None:
            self.advance(now)
        return self._plan is not None or self._jog is not None

    def motion_end(self) -> float | None:
        """When the running motion ends (a jog: its watchdog deadline); None when still."""
        if self._plan is not None:
            return self._plan_end
        if self._jog is not None:
            return self._jog.last_command + self.jog_watchdog_s
        return None

    def stop(self, now: float, *, immediate: bool = False) -> None:
        """Stop: decelerate along the path at the plan's deceleration (or freeze at once);
        `motion_end()` becomes the moment the arm is still. Ends a jog at once."""
        self.advance(now)
        self._jog = None
        if self._plan is None:
            return
        if immediate:
            self._plan = None
            return
        stop_plan = self._plan.stopped(now - self._plan_start)
        self._start_plan(stop_plan, now)

    def record(self, now: float, line: int | None = None) -> TrajectorySample:
        """Advance to `now` and store a sample (with `line`, or the current line)."""
        self.advance(now)
        return self._record(now, line)

    def clear_fault(self) -> None:
        self.fault = None

    # --- moves -------------------------------------------------------------------------

    def move_joint(
        self,
        target: Pose | Joints,
        now: float,
        *,
        close: float | None = None,
        shortcut: bool = False,
    ) -> Plan:
        """MOV target [, close] [TYPE shortcut]: joint interpolation (see `motion.plan_joint`)."""
        return self._begin(
            now,
            lambda q: motion.plan_joint(
                q, target, self._speeds, self.frames, close=close, shortcut=shortcut
            ),
        )

    def move_linear(self, target: Pose | Joints, now: float, *, close: float | None = None) -> Plan:
        """MVS target [, close]: straight-line move (see `motion.plan_linear`)."""
        return self._begin(
            now, lambda q: motion.plan_linear(q, target, self._speeds, self.frames, close=close)
        )

    def move_linear_offset(self, distance: float, now: float) -> Plan:
        """``MVS , d``: `distance` mm along the current tool Z."""
        return self._begin(
            now, lambda q: motion.plan_linear_offset(q, distance, self._speeds, self.frames)
        )

    def move_arc(self, start: Pose, via: Pose, end: Pose, now: float) -> Plan:
        """MVR start, via, end."""
        return self._begin(
            now, lambda q: motion.plan_arc(q, start, via, end, self._speeds, self.frames)
        )

    def move_arc_ref(self, start: Pose, end: Pose, ref: Pose, now: float) -> Plan:
        """MVR2 start, end, ref (the arc not passing ref)."""
        return self._begin(
            now, lambda q: motion.plan_arc_ref(q, start, end, ref, self._speeds, self.frames)
        )

    def move_arc_centre(self, start: Pose, end: Pose, centre: Pose, now: float) -> Plan:
        """MVR3 start, end, centre."""
        return self._begin(
            now,
            lambda q: motion.plan_arc_centre(q, start, end, centre, self._speeds, self.frames),
        )

    def move_circle(self, start: Pose, via1: Pose, via2: Pose, now: float) -> Plan:
        """MVC start, via1, via2 (full circle back to start)."""
        return self._begin(
            now, lambda q: motion.plan_circle(q, start, via1, via2, self._speeds, self.frames)
        )

    def move_arch(self, target: Pose | Joints, now: float, *, height: float | None = None) -> Plan:
        """MVA target: lift, traverse, lower (see `motion.plan_arch`)."""
        h = motion.ARCH_HEIGHT_MM if height is None else height
        return self._begin(
            now, lambda q: motion.plan_arch(q, target, self._speeds, self.frames, height=h)
        )

    def to_joints(self, target: Pose, *, use_flags: bool = True) -> Joints:
        """IK of a pose under the active TOOL/BASE near the current joints (PTOJ)."""
        try:
            return ik(
                target,
                self._joints,
                self._tool,
                self._base,
                use_fl1=use_flags,
                use_fl2=use_flags,
                interference=self._interference,
            )
        except KinematicsError as exc:
            raise from_kinematics(exc) from exc

    def to_pose(self, joints: Sequence[float]) -> Pose:
        """FK under the active TOOL/BASE (JTOP)."""
        return fk(joints, self._tool, self._base)

    # --- jog ---------------------------------------------------------------------------

    def jog(
        self,
        mode: JogMode,
        directions: Sequence[int],
        now: float,
        *,
        inch: JogInch = JogInch.OFF,
    ) -> None:
        """One JOG command: keep moving in `mode` along `directions` (-1/0/+1 per axis,
        X/J1 first) until `jog_stop`, or until no JOG arrives for `jog_watchdog_s`.
        All-zero directions stop. With inching, one small step (`INCH_HIGH`/`INCH_LOW`)."""
        self.advance(now)
        if not self._servo:
            raise ServoOff("the servo is OFF: jog refused")
        if self._plan is not None:
            raise JogRefused("JOG operation cannot be accepted while a move runs")
        if mode not in (JogMode.JOINT, JogMode.XYZ, JogMode.TOOL):
            raise JogRefused(f"jog mode {mode.name} is not simulated")
        dirs = tuple(int(d > 0) - int(d < 0) for d in directions[:6])
        if not any(dirs):
            self._jog = None
            return
        if inch is not JogInch.OFF:
            self._jog = None
            self._inch(mode, dirs, INCH_HIGH if inch is JogInch.HIGH else INCH_LOW, now)
            return
        if self._jog is not None and (self._jog.mode, self._jog.directions) == (mode, dirs):
            self._jog.last_command = now
        else:
            self._jog = _Jog(mode, dirs, now)

    def jog_stop(self, now: float) -> None:
        """Stop jogging at once (the jog speed is low; no deceleration modelled)."""
        self.advance(now)
        self._jog = None

    def _inch(self, mode: JogMode, dirs: tuple[int, ...], step: float, now: float) -> None:
        d = [float(v) * step for v in dirs] + [0.0] * (6 - len(dirs))
        if mode is JogMode.JOINT:
            target_j = Joints.of(q + dq for q, dq in zip(self._joints, d, strict=True))
            self.move_joint(target_j, now)
            return
        here = self.pose
        if mode is JogMode.XYZ:
            target = replace(
                here,
                x=here.x + d[0],
                y=here.y + d[1],
                z=here.z + d[2],
                a=here.a + d[3],
                b=here.b + d[4],
                c=here.c + d[5],
            )
        else:
            target = pose_mul(here, Pose(d[0], d[1], d[2], d[3], d[4], d[5]))
        self.move_linear(target, now)

    def _advance_jog(self, now: float) -> None:
        jog = self._jog
        assert jog is not None
        deadline = jog.last_command + self.jog_watchdog_s
        end = min(now, deadline)
        t = self._time
        while t < end:
            dt = min(JOG_STEP_S, end - t)
            try:
                self._joints = motion.jog_step(
                    self._joints, jog.mode, jog.directions, dt, self._op_override, self.frames
                )
            except KinematicsError as exc:
                self.fault = from_kinematics(exc)
                self._jog = None
                return
            t += dt
        if now >= deadline:
            self._jog = None

    # --- internals ---------------------------------------------------------------------

    def _begin(self, now: float, build: Callable[[Joints], Plan]) -> Plan:
        self.advance(now)
        if not self._servo:
            raise ServoOff("the servo is OFF: move refused")
        if self._plan is not None or self._jog is not None:
            raise ArmBusy("the arm is still moving")
        try:
            plan = build(self._joints)
        except KinematicsError as exc:
            raise from_kinematics(exc) from exc
        self._start_plan(plan, now)
        return plan

    def _start_plan(self, plan: Plan, now: float) -> None:
        self._plan = plan
        self._plan_start = now
        self._plan_end = now + plan.duration
        self.recorder.add_event(MoveEvent(now, plan.kind, plan, self._line))
        if plan.duration <= 0.0:
            self._joints = plan.end_joints
            self._plan = None
        self._record(now)

    def _record(self, now: float, line: int | None = None) -> TrajectorySample:
        sample = TrajectorySample(
            now,
            self._joints,
            self.pose,
            tuple(self._hands),
            self._line if line is None else line,
        )
        self.recorder.add_sample(sample)
        return sample


def _check_percent(name: str, value: float) -> None:
    if value not in OVERRIDE_PERCENT:
        raise ValueError(f"{name} must be {span_text(OVERRIDE_PERCENT)} %, got {value}")


def _check_program_percent(name: str, value: float) -> None:
    """A program's OVRD/JOVRD (`melfa.protocol.limits.is_program_override`)."""
    if not is_program_override(value):
        raise ValueError(f"{name} must be {PROGRAM_OVERRIDE_TEXT}, got {value}")
