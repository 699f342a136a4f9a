"""The URDF's forward kinematics is melfa.kin's: parse the XML, compose its joint
transforms at random joint values (as robot_state_publisher does), compare the flange."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from melfa.kin import JOINT_LIMITS, fk_matrix
from melfa.ros.messages import JOINT_STATE_NAMES
from melfa.ros.urdf import rv6s_urdf

ROBOT = ET.fromstring(rv6s_urdf())


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    out: np.ndarray = rz @ ry @ rx
    return out


def origin_of(joint: ET.Element) -> np.ndarray:
    origin = joint.find("origin")
    assert origin is not None
    t = np.eye(4)
    t[:3, :3] = rpy_matrix(*(float(v) for v in origin.get("rpy", "0 0 0").split()))
    t[:3, 3] = [float(v) for v in origin.get("xyz", "0 0 0").split()]
    return t


def axis_rotation(axis: list[float], angle: float) -> np.ndarray:
    x, y, z = axis
    c, s, v = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    t = np.eye(4)
    t[:3, :3] = [
        [c + x * x * v, x * y * v - z * s, x * z * v + y * s],
        [y * x * v + z * s, c + y * y * v, y * z * v - x * s],
        [z * x * v - y * s, z * y * v + x * s, c + z * z * v],
    ]
    return t


def urdf_transform(positions: dict[str, float], tip: str = "tool0") -> np.ndarray:
    """base_link → ``tip`` by walking the joints from the tip up."""
    by_child = {j.find("child").get("link"): j for j in ROBOT.iter("joint")}  # type: ignore[union-attr]
    chain = []
    link = tip
    while link in by_child:
        joint = by_child[link]
        chain.append(joint)
        parent = joint.find("parent")
        assert parent is not None
        link = parent.get("link", "")
    assert link == "base_link"
    t = np.eye(4)
    for joint in reversed(chain):
        t = t @ origin_of(joint)
        if joint.get("type") == "revolute":
            axis = [float(v) for v in joint.find("axis").get("xyz").split()]  # type: ignore[union-attr]
            t = t @ axis_rotation(axis, positions[joint.get("name", "")])
    return t


def test_joint_names_and_limits_match_joint_states() -> None:
    revolute = [j for j in ROBOT.iter("joint") if j.get("type") == "revolute"]
    assert [j.get("name") for j in revolute] == list(JOINT_STATE_NAMES)
    for joint, (low, high) in zip(revolute, JOINT_LIMITS, strict=True):
        limit = joint.find("limit")
        assert limit is not None
        assert float(limit.get("lower", "nan")) == pytest.approx(math.radians(low), abs=1e-9)
        assert float(limit.get("upper", "nan")) == pytest.approx(math.radians(high), abs=1e-9)


def random_joints(count: int, seed: int = 17) -> list[tuple[float, ...]]:
    """Joint vectors drawn uniformly inside the limits (numpy's own generator: roslibpy's
    reactor thread, still running from other tests, uses the `random` module, which
    Hypothesis would take for a strategy misusing it)."""
    rng = np.random.default_rng(seed)
    low, high = np.array(JOINT_LIMITS).T
    return [tuple(float(v) for v in rng.uniform(low, high)) for _ in range(count)]


@pytest.mark.parametrize("joints", random_joints(300))
def test_the_urdf_flange_is_melfa_kin_flange(joints: tuple[float, ...]) -> None:
    positions = {name: math.radians(q) for name, q in zip(JOINT_STATE_NAMES, joints, strict=True)}
    ours = urdf_transform(positions)
    kin = fk_matrix(joints)
    assert np.allclose(ours[:3, 3] * 1000, kin[:3, 3], atol=1e-4)  # mm
    assert np.allclose(ours[:3, :3], kin[:3, :3], atol=1e-7)  # URDF keeps 9 decimals


def test_home_puts_the_flange_where_the_controller_says() -> None:
    home = urdf_transform(
        {
            name: math.radians(q)
            for name, q in zip(JOINT_STATE_NAMES, (0, 0, 90, 0, 90, 0), strict=True)
        }
    )
    assert np.allclose(home[:3, 3], (0.400, 0.0, 0.645), atol=1e-9)
