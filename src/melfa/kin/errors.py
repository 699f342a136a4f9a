"""Kinematics errors: a target the RV-6S cannot take.

These are *refusals by the robot model*, not misuse of the API: a pose out of reach, a
singular pose, a joint outside its range. The simulator maps them to controller error
numbers (see `melfa.sim.arm`).
"""

from __future__ import annotations

import enum


class KinematicsError(Exception):
    """Base class: the RV-6S cannot reach or hold the requested position."""


class UnreachableReason(enum.Enum):
    """Why a pose has no inverse-kinematics solution."""

    OUT_OF_REACH = "out of reach"
    """The wrist centre is farther (or closer) than the arm can stretch (or fold)."""
    SINGULAR = "singular"
    """The path crosses a singularity (joints would have to jump)."""


class Unreachable(KinematicsError):
    """No joint solution for a pose (out of reach or singular)."""

    def __init__(self, reason: UnreachableReason, detail: str = "") -> None:
        self.reason = reason
        self.detail = detail
        msg = f"position {reason.value}"
        super().__init__(f"{msg}: {detail}" if detail else msg)


class LimitExceeded(KinematicsError):
    """A joint vector outside the RV-6S operating range (per-joint or interference)."""


class JointLimitExceeded(LimitExceeded):
    """One joint outside its range. `joint` is 1-based (J1..J6); angles in degrees."""

    def __init__(self, joint: int, value: float, limits: tuple[float, float]) -> None:
        self.joint = joint
        self.value = value
        self.limits = limits
        super().__init__(
            f"J{joint} = {value:.2f} deg is outside its range {limits[0]:g} .. {limits[1]:g} deg"
        )


class InterferenceLimitExceeded(LimitExceeded):
    """Joints inside their own ranges but the arm would hit itself (rv6s.md §3)."""

    def __init__(self, rule: str, joints: tuple[float, ...]) -> None:
        self.rule = rule
        self.joints = joints
        shown = ", ".join(f"{j:.2f}" for j in joints)
        super().__init__(f"interference limit violated: {rule} (joints {shown})")
