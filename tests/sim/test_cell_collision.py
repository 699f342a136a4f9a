"""Collisions of the arm's capsules (links and gripper) with fixtures, parts and the table:
the capsule model, the distances, and pre-flight findings on the line that caused them,
with a 5 mm plate that the path's coarse samples step over."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.kin import capsules
from melfa.kin.model import HOME
from melfa.sim.debug.cell import Cell, Gripper, Shape, Solid
from melfa.sim.debug.cell_collision import ArmBodies
from melfa.sim.debug.preflight import Kind, preflight

HOME_Q = np.array([list(HOME)])


def box(name: str, size: tuple[float, float, float], at: tuple[float, float, float]) -> Solid:
    return Solid(name, Shape.BOX, size, at)


def test_the_capsules_follow_the_kinematic_model() -> None:
    starts, ends = capsules.segments(HOME_Q, tool_length=60)
    seg = {n: (s, e) for n, s, e in zip(capsules.names(True), starts[0], ends[0], strict=True)}
    # at HOME the flange is at (400, 0, 645) pointing down, the wrist centre 85 mm above
    # it; the wrist's capsule (radius 45) ends at the flange's face
    assert seg["wrist"][0] == pytest.approx((400, 0, 730), abs=1e-9)
    assert seg["wrist"][1] == pytest.approx((400, 0, 645 + 45), abs=1e-9)
    assert seg["gripper"][1] == pytest.approx((400, 0, 585), abs=1e-9)
    assert seg["upper arm"][0] == pytest.approx((85, 0, 350), abs=1e-9)
    # a BASE moves every capsule with it
    base = np.eye(4)
    base[:3, 3] = (1000, 0, 0)
    moved, _ = capsules.segments(HOME_Q, base=base, tool_length=60)
    assert moved[0] - starts[0] == pytest.approx(np.tile([1000, 0, 0], (6, 1)))


def test_reach_bounds_how_far_each_capsule_moves_per_radian() -> None:
    reach = capsules.reach(60, 30)
    names = capsules.names(True)
    assert reach[:, names.index("base")] == pytest.approx(np.zeros(6))  # J1 turns it in place
    assert reach[1:, names.index("upper arm")][1:] == pytest.approx(np.zeros(4))
    # J1 turning 0.01 rad moves no point of the arm more than the bound: check at HOME
    q2 = HOME_Q + np.degrees([[0.01, 0, 0, 0, 0, 0]])
    a, b = capsules.segments(HOME_Q, tool_length=60)
    c, d = capsules.segments(q2, tool_length=60)
    moved = np.maximum(np.linalg.norm(c - a, axis=2), np.linalg.norm(d - b, axis=2))[0]
    assert np.all(moved <= 0.01 * reach[0] + 1e-9)


@pytest.mark.parametrize(("top", "clearance"), [(635.0, 10.0), (645.0, 0.0), (655.0, -10.0)])
def test_the_clearance_of_the_wrist_above_a_box_under_the_flange(
    top: float, clearance: float
) -> None:
    """At HOME the wrist's capsule (radius 45) ends at the flange's face, 645; a box
    under it, its top at `top`."""
    bodies = ArmBodies(None)
    table = box("jig", (100, 100, top), (400, 0, 0))
    clear = bodies.clearance(HOME_Q, [table], None, threshold=np.inf)
    wrist = bodies.names.index("wrist")
    assert clear[0, wrist, 0] == pytest.approx(clearance, abs=1e-9)


def test_cylinders_turned_boxes_and_the_table() -> None:
    bodies = ArmBodies(Gripper(length=60, radius=30))
    g = bodies.names.index("gripper")
    # gripper tip (400, 0, 585), radius 30: lowest point 555; a puck beside it
    puck = Solid("puck", Shape.CYLINDER, (50, 50, 600), (400, 70, 0))
    turned = Solid("bar", Shape.BOX, (200, 10, 600), (400, 70, 0), rz=90)  # 10 × 200 now
    clear = bodies.clearance(HOME_Q, [puck, turned], floor=500.0, threshold=np.inf)
    assert clear[0, g, 0] == pytest.approx(70 - 25 - 30)
    assert clear[0, g, 1] < 0  # turned, the bar reaches under the gripper's axis
    assert clear[0, g, 2] == pytest.approx(555 - 500)
    assert clear[0, bodies.names.index("base"), 2] == np.inf  # the base stands on it


FAST = "SERVO ON\nOVRD 100\nMOV J1\nMOV J2\nEND\n"
FAST_POINTS = "DEF JNT J1=(-143,0,90,0,90,0)\nDEF JNT J2=(150,0,90,0,90,0)\n"


def test_a_5_mm_plate_between_two_coarse_samples_is_found_on_its_line() -> None:
    """A thin pin (radius 2) on the flange swings through a plate 5 mm thick: the path's
    samples (at most 20 per move) are tens of mm apart there, the check still finds it."""
    pin = Gripper(length=100, radius=2)
    # across the pin's swing where J1 = 30°: 100 mm along the radius, 5 mm thick
    at = (400 * math.cos(math.radians(30)), 400 * math.sin(math.radians(30)), 555.0)
    plate = Solid("plate", Shape.BOX, (100, 5, 40), at, rz=30)
    r = preflight(FAST, FAST_POINTS, cell=Cell(floor_z=None, fixtures=(plate,), gripper=pin))
    (hit,) = r.collisions
    assert (hit.body, hit.obstacle, hit.line, hit.move) == ("gripper", "plate", 4, 1)
    assert not r.ok and [f.kind for f in r.errors] == [Kind.COLLISION]
    assert "line 4: the move takes the gripper" in r.errors[0].message
    # the coarse samples of that move step over the plate: none is within 10 mm of its
    # middle plane (the pin is 2 mm thick, the plate 5 mm)
    swing = [p for p in r.path if p.move == 1]
    assert len(swing) <= 21
    s30, c30 = math.sin(math.radians(30)), math.cos(math.radians(30))
    assert min(abs(-p.x * s30 + p.y * c30) for p in swing if p.x > 0) > 10
    # without the plate, nothing
    clear = preflight(FAST, FAST_POINTS, cell=Cell(floor_z=None, gripper=pin))
    assert clear.collisions == () and clear.ok


PICK = """SERVO ON
OVRD 100
MOV P1, -50
MVS P1
HCLOSE 1
MVS P1, -50
END
"""


def test_a_gripper_too_short_for_the_part_collides_with_it_on_the_approach() -> None:
    bench = box("bench", (400, 600, 120), (400, 25, 0))
    puck = Solid("a", Shape.CYLINDER, (50, 50, 20), (400, -100, 120))
    points = "DEF POS P1=(400,-100,230,180,0,180)(7,0)\n"
    ok = Gripper(grip=100, length=50, radius=20)  # body ends 40 mm above the puck's top
    r = preflight(PICK, points, cell=Cell(fixtures=(bench,), parts=(puck,), gripper=ok))
    assert r.collisions == () and r.hands[0].part == "a"
    long_body = Gripper(grip=100, length=80, radius=20)  # reaches 10 mm into it
    r = preflight(PICK, points, cell=Cell(fixtures=(bench,), parts=(puck,), gripper=long_body))
    hits = {(c.body, c.obstacle, c.line) for c in r.collisions}
    assert ("gripper", "a", 4) in hits
    # its tip (radius 20) ends 150 mm up, 10 mm above the puck's top: 10 mm into it
    deepest = max(c.depth for c in r.collisions if c.obstacle == "a")
    assert deepest == pytest.approx(10.0, abs=0.5)


angle = st.floats(min_value=-150, max_value=150, allow_nan=False)
turn = st.floats(min_value=-20, max_value=20, allow_nan=False)


@given(st.tuples(*[angle] * 6), st.tuples(*[turn] * 6))
def test_no_point_moves_further_than_the_bound_between_two_samples(
    q0: tuple[float, ...], dq: tuple[float, ...]
) -> None:
    """The bound the dense check relies on: joints moving straight from q0 to q0 + dq, no
    point of any capsule (its axis, and so its surface) leaves the ball the bound gives."""
    bodies = ArmBodies(Gripper(length=80, radius=25))
    ends = np.array([q0, np.add(q0, dq)])
    bound = bodies.moved(ends, bodies.place(ends))[0]  # (C,)
    path = np.array(q0) + np.linspace(0, 1, 41)[:, None] * np.array(dq)
    starts, tips = capsules.segments(path, tool_length=80)
    for points in (starts, tips, (starts + tips) / 2):
        moved = np.linalg.norm(points - points[0], axis=2).max(axis=0)
        assert np.all(moved <= bound + 1e-6)


def test_the_tool_below_the_table_is_said_once_not_again_for_the_wrist() -> None:
    low = "SERVO ON\nMOV P1\nMVS P2\nEND\n"
    points = "DEF POS P1=(500,0,100,180,0,180)(7,0)\nDEF POS P2=(500,0,-20,180,0,180)(7,0)\n"
    r = preflight(low, points)
    assert ("wrist", "table", 3) in {(c.body, c.obstacle, c.line) for c in r.collisions}
    assert [f.kind for f in r.errors] == [Kind.BELOW_FLOOR]
