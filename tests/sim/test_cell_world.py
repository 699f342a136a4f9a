"""The cell during a run: grasping, dropping, stacking, sensors and conveyors (pure world),
and the same through a simulated run (pre-flight) with its hand actions on their lines."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from melfa.sim.debug.cell import Cell, CellError, Conveyor, Gripper, Sensor, Shape, Solid
from melfa.sim.debug.cell_world import CellWorld, HandChange, footprints_overlap
from melfa.sim.debug.preflight import preflight

HAND_DOWN = (0.0, 0.0, 0.0, 180.0, 0.0, 180.0)


def puck(name: str, x: float, y: float, z: float, d: float = 50.0, h: float = 20.0) -> Solid:
    return Solid(name, Shape.CYLINDER, (d, d, h), (x, y, z))


def flange(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """A hand-down flange at (x, y, z) turned `yaw` degrees about the vertical."""
    r = math.radians(yaw)
    t = np.eye(4)
    rz = np.array([[math.cos(r), -math.sin(r), 0], [math.sin(r), math.cos(r), 0], [0, 0, 1]])
    t[:3, :3] = rz @ np.diag([1.0, -1.0, -1.0])  # tool Z points down
    t[:3, 3] = (x, y, z)
    return t


GRIP = Gripper(hand=1, grip=100.0, tolerance=10.0, length=50.0, radius=20.0)


def world(*parts: Solid, **kw: object) -> CellWorld:
    return CellWorld(Cell(floor_z=0.0, parts=parts, gripper=GRIP, **kw))  # type: ignore[arg-type]


def test_a_part_within_the_tolerance_is_carried_and_drops_onto_the_table() -> None:
    w = world(puck("a", 300, 0, 0))
    # grip point 100 mm below the flange: the puck's centre is at z = 10
    took = w.close(1.0, flange(303, 4, 110), HAND_DOWN, 12)
    assert took.part == "a" and took.change is HandChange.CLOSE and took.line == 12
    assert w.held == "a" and w.parts(flange(303, 4, 110))[0].held
    # carried 200 mm along Y and 150 mm up, turned 30° about the vertical
    let_go = w.open(2.0, flange(303, 204, 260, yaw=30), HAND_DOWN, 20)
    assert let_go.part == "a" and let_go.on == "table"
    # it was taken 3 mm and 4 mm off the flange's axis: that offset turned 30° with it
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    expected = (303 - 3 * c + 4 * s, 204 - 3 * s - 4 * c, 0)
    assert let_go.landed == pytest.approx(expected, abs=1e-9)
    assert let_go.drop == pytest.approx(150.0)
    (a,) = w.parts()
    assert a.position == pytest.approx(expected) and a.rz == pytest.approx(30.0)
    assert not a.held and a.on == "table"


def test_a_part_outside_the_tolerance_stays_and_the_hand_closes_on_nothing() -> None:
    w = world(puck("a", 300, 0, 0))
    act = w.close(1.0, flange(311, 0, 110), HAND_DOWN, 3)  # 11 mm off
    assert act.part is None and w.held is None
    assert w.open(2.0, flange(0, 300, 300), HAND_DOWN, 4).part is None
    assert w.parts()[0].position == (300, 0, 0)


def test_the_nearest_of_two_parts_in_reach_is_taken() -> None:
    pair = (puck("a", 300, 0, 0, d=10), puck("b", 311, 0, 0, d=10))  # 1 mm apart
    # the grip point 100 mm below the flange; the pucks' centres are at z = 10
    assert world(*pair).close(0, flange(304, 0, 110), HAND_DOWN, 1).part == "a"
    assert world(*pair).close(0, flange(308, 0, 110), HAND_DOWN, 1).part == "b"


def test_a_part_let_go_pushed_into_another_rests_on_top_of_it() -> None:
    w = world(puck("a", 300, 0, 0), puck("b", 0, 300, 0))
    w.close(0, flange(0, 300, 110), HAND_DOWN, 1)
    pushed = w.open(1, flange(300, 0, 120), HAND_DOWN, 2)  # b's bottom 10 mm into a
    assert pushed.on == "a" and pushed.landed == pytest.approx((300, 0, 20))


def test_parts_stack_and_side_by_side_parts_do_not() -> None:
    w = world(puck("a", 300, 0, 0), puck("b", 0, 300, 0), puck("c", 0, -300, 0))
    w.close(0, flange(0, 300, 110), HAND_DOWN, 1)
    on_a = w.open(1, flange(310, 0, 200), HAND_DOWN, 2)  # 10 mm off-centre: still on a
    assert on_a.on == "a" and on_a.landed == pytest.approx((310, 0, 20))
    w.close(2, flange(0, -300, 110), HAND_DOWN, 3)
    beside = w.open(3, flange(250, 0, 200), HAND_DOWN, 4)  # touching a, not over it
    assert beside.on == "table" and beside.landed == pytest.approx((250, 0, 0))


def test_taking_the_bottom_part_lets_the_one_on_it_drop() -> None:
    w = world(puck("low", 300, 0, 0), puck("top", 300, 0, 20))
    assert [p.on for p in w.parts()] == ["table", "low"]
    w.close(0, flange(300, 0, 110), HAND_DOWN, 1)  # the lower puck's centre: z = 10
    assert w.held == "low"
    top = w.parts()[1]
    assert top.position == pytest.approx((300, 0, 0)) and top.on == "table"


def test_parts_defined_in_the_air_rest_on_what_is_below_them() -> None:
    bench = Solid("bench", Shape.BOX, (400, 400, 100), (300, 0, 0))
    w = CellWorld(Cell(fixtures=(bench,), parts=(puck("a", 300, 0, 180),), gripper=GRIP))
    assert w.parts()[0].position == (300, 0, 100) and w.parts()[0].on == "bench"


def test_footprints_of_boxes_and_cylinders() -> None:
    box = Solid("b", Shape.BOX, (100, 20, 10), (0, 0, 0))
    assert footprints_overlap(box, puck("p", 0, 20, 0, d=30))  # 10 mm into a 15 mm radius
    assert not footprints_overlap(box, puck("p", 0, 24.6, 0, d=30))  # 0.4 mm: under 0.5
    turned = Solid("t", Shape.BOX, (100, 20, 10), (0, 40, 0), rz=90)  # now 20 × 100
    assert footprints_overlap(box, turned)
    assert not footprints_overlap(box, Solid("t", Shape.BOX, (100, 20, 10), (0, 40, 0)))
    assert footprints_overlap(turned, puck("p", 0, 85, 0, d=20))
    assert not footprints_overlap(turned, puck("p", 30, 85, 0, d=20))


def test_a_conveyor_moves_the_parts_on_it_while_its_output_is_on() -> None:
    belt = Conveyor("belt", 10, (600, 100, 80), (300, 0, 0), (100.0, 0.0))
    w = world(puck("a", 100, 0, 80), puck("off", 100, 300, 0), conveyors=(belt,))
    assert w.parts()[0].on == "belt"
    w.advance(5.0)
    assert w.parts()[0].position == (100, 0, 80)  # output off: nothing moves
    w.set_output(5.0, 10, 1)
    assert w.running
    w.advance(7.5)
    assert w.parts()[0].position == pytest.approx((350, 0, 80))
    assert w.parts()[1].position == (100, 300, 0)  # not on the belt
    w.advance(20.0)
    assert w.parts()[0].position == pytest.approx((600, 0, 80))  # stopped at the end
    w.set_output(20.0, 10, 0)
    assert not w.running


def test_a_sensor_sees_a_part_centre_in_its_region() -> None:
    sensor = Sensor("at pick", 8, (450, -50, 0), (650, 50, 200))
    belt = Conveyor("belt", 10, (600, 100, 80), (300, 0, 0), (100.0, 0.0))
    w = world(puck("a", 100, 0, 80), conveyors=(belt,), sensors=(sensor,))
    assert w.inputs() == {8: 0}
    w.set_output(0.0, 10, 1)
    w.advance(3.4)  # centre at x = 440
    assert w.inputs() == {8: 0}
    w.advance(3.6)  # x = 460
    assert w.inputs() == {8: 1}
    w.set_output(3.6, 10, 0)
    w.close(4.0, flange(460, 0, 190), HAND_DOWN, 1)
    assert w.inputs() == {8: 0}  # held, nowhere said
    assert w.inputs(flange(460, 0, 190)) == {8: 1}  # held inside the region
    assert w.inputs(flange(460, 0, 400)) == {8: 0}  # lifted out


def test_the_cell_json_round_trips_and_says_what_is_wrong() -> None:
    cell = Cell(
        fixtures=(Solid("bench", Shape.BOX, (100, 200, 50), (300, 0, 0), rz=15),),
        parts=(puck("a", 300, 0, 50),),
        gripper=GRIP,
        sensors=(Sensor("s", 8, (0, 0, 0), (1, 1, 1)),),
        conveyors=(Conveyor("belt", 10, (600, 100, 80), (300, 0, 0), (100.0, 0.0)),),
    )
    assert Cell.from_json(json.dumps(cell.to_json())) == cell
    for data, message in [
        ({"parts": [{"name": "a", "shape": "cone"}]}, "part 'a': shape must be box or cylinder"),
        ({"parts": [{"name": "a", "shape": "cylinder", "height": 3}]}, "part 'a': diameter"),
        (
            {"parts": [{"name": "a", "size": [1, 0, 1], "position": [0, 0, 0]}]},
            "size y must be more than 0",
        ),
        ({"parts": [{"name": "a", "size": [1, 1, 1]}]}, r"part 'a': position must be \[x, y, z\]"),
        ({"parts": [{"name": "a", "size": [1, 1, 1], "position": [0, 0, 0], "mass": 1}]}, "mass"),
        ({"gripper": {"hand": 9}}, "hand must be a hand number 1–8"),
        ({"sensors": [{"name": "s", "input": -1, "min": [0, 0, 0], "max": [1, 1, 1]}]}, "input"),
        (
            {"conveyors": [{"name": "c", "output": 1, "size": [1, 1, 1], "position": [0, 0, 0]}]},
            "velocity must be",
        ),
    ]:
        with pytest.raises(CellError, match=message):
            Cell.from_json(data)
    two = {"size": [1, 1, 1], "position": [0, 0, 0]}
    with pytest.raises(CellError, match="two parts are named 'a'"):
        Cell.from_json({"parts": [{"name": "a", **two}, {"name": "a", **two}]})


# ---------------------------------------------------------------- through a simulated run

PICK = """SERVO ON
OVRD 100
MOV P1, -50
MVS P1
HCLOSE 1
MVS P1, -50
MOV P2, -50
MVS P2
HOPEN 1
MVS P2, -50
END
"""

PICK_POINTS = """DEF POS P1=(400,-100,230,180,0,180)(7,0)
DEF POS P2=(400,150,260,180,0,180)(7,0)
"""


def test_a_run_carries_the_part_from_p1_to_p2_and_records_each_hand_action() -> None:
    bench = Solid("bench", Shape.BOX, (400, 600, 120), (400, 25, 0))
    cell = Cell(fixtures=(bench,), parts=(puck("a", 400, -100, 120),), gripper=GRIP)
    r = preflight(PICK, PICK_POINTS, cell=cell)
    assert r.finished
    close, open_ = r.hands
    assert (close.change, close.line, close.part) == (HandChange.CLOSE, 5, "a")
    assert close.pose[:3] == pytest.approx((400, -100, 230))
    assert (open_.change, open_.line, open_.part, open_.on) == (HandChange.OPEN, 9, "a", "bench")
    assert open_.drop == pytest.approx(30.0)  # released 30 mm above the bench
    assert 0 < close.time < open_.time < r.duration
    (a,) = r.parts
    assert a.position == pytest.approx((400, 150, 120), abs=1e-6) and a.on == "bench"
    assert r.to_json()["parts"][0]["name"] == "a"


FEED = """SERVO ON
OVRD 100
M_OUT(10) = 1
WAIT M_IN(8) = 1
M_OUT(10) = 0
MOV P1, -50
MVS P1
HCLOSE 1
MVS P1, -50
END
"""


def test_a_conveyor_brings_the_part_to_a_sensor_the_program_waits_for() -> None:
    belt = Conveyor("belt", 10, (600, 100, 80), (300, 0, 0), (50.0, 0.0))
    sensor = Sensor("at pick", 8, (495, -50, 0), (700, 50, 200))
    cell = Cell(parts=(puck("a", 100, 0, 80),), gripper=GRIP, conveyors=(belt,), sensors=(sensor,))
    # the belt takes 395 / 50 = 7.9 s to bring the centre into the sensor's region
    points = "DEF POS P1=(495.5,0,190,180,0,180)(7,0)\n"
    # (the belt's top is at z = 80: the puck's centre at 90, the flange 100 mm above it)
    r = preflight(FEED, points, cell=cell)
    assert r.finished
    (close,) = r.hands
    assert close.part == "a" and close.line == 8
    assert close.time > 7.9
    assert r.parts[0].held


def test_the_parts_go_back_when_a_debugger_runs_the_program_again() -> None:
    from melfa.sim.debug.cell_run import CellRun
    from melfa.sim.debug.engine import INSTANT, Debugger

    bench = Solid("bench", Shape.BOX, (400, 600, 120), (400, 25, 0))
    cell = Cell(fixtures=(bench,), parts=(puck("a", 400, -100, 120),), gripper=GRIP)
    d = Debugger(PICK, PICK_POINTS, clock=lambda: 0.0, speed=INSTANT)
    run = CellRun.follow(cell, d)
    for _ in range(2):
        d.run()
        while d.poll() is None:
            pass
        assert [a.part for a in run.actions] == ["a", "a"]  # this run's, not the last one's too
        assert run.parts()[0].position == pytest.approx((400, 150, 120))
    run.detach()
    assert d.io.before_read is None and not d.arm.recorder.listeners
