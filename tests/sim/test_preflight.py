"""Pre-flight: findings from a simulated run's trajectory, each on the line that caused it."""

from __future__ import annotations

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.sim.debug.cell import Box, Cell, CellError
from melfa.sim.debug.engine import DebugError
from melfa.sim.debug.preflight import Kind, Limits, Severity, preflight, report_text

LOW = "SERVO ON\nMOV P1\nMVS P2\nMOV P1\nEND\n"
LOW_POINTS = "DEF POS P1=(500,0,100,180,0,180)(7,0)\nDEF POS P2=(500,0,-20,180,0,180)(7,0)\n"


def kinds(report: object) -> set[tuple[Kind, int | None]]:
    return {(f.kind, f.line) for f in report.findings}  # type: ignore[attr-defined]


def test_a_move_below_the_table_is_an_error_on_its_line_with_its_path_segment() -> None:
    r = preflight(LOW, LOW_POINTS)
    assert not r.ok and r.finished
    below = [f for f in r.findings if f.kind is Kind.BELOW_FLOOR]
    assert below[0].line == 3 and below[0].severity is Severity.ERROR
    assert "20.0 mm below the table" in below[0].message
    seg = below[0].segment
    assert seg is not None and seg.move == 1 and seg.start <= seg.end
    # the path the 3D view draws has the low points inside that segment
    low = [p for p in r.path if p.move == seg.move and seg.start <= p.time <= seg.end]
    assert low and min(p.z for p in low) == pytest.approx(-20.0, abs=0.01)
    assert all(p.z < 0 for p in low)


def test_a_lower_table_or_none_accepts_the_same_program() -> None:
    assert preflight(LOW, LOW_POINTS, cell=Cell(floor_z=-50.0)).ok
    assert preflight(LOW, LOW_POINTS, cell=Cell(floor_z=None)).ok


def test_a_box_obstacle_is_an_error() -> None:
    box = Box("feeder", (450.0, -50.0, 50.0), (650.0, 50.0, 150.0))
    r = preflight(LOW, LOW_POINTS, cell=Cell(floor_z=-50.0, boxes=(box,)))
    hits = [f for f in r.findings if f.kind is Kind.IN_OBSTACLE]
    assert {f.line for f in hits} == {2, 3, 4} and "'feeder'" in hits[0].message
    assert not r.ok


def test_cycle_time_and_joint_margins() -> None:
    r = preflight(LOW, LOW_POINTS, cell=Cell(floor_z=-50.0))
    assert r.cycle_time is not None and 0.3 < r.cycle_time < 5.0
    assert [j.joint for j in r.joints] == [1, 2, 3, 4, 5, 6]
    j2 = r.joints[1]
    assert j2.limit == 135.0 and j2.margin == pytest.approx(135.0 - j2.value)
    assert j2.line in (2, 3, 4)
    tight = preflight(LOW, LOW_POINTS, cell=Cell(floor_z=-50.0), limits=Limits(joint_margin_deg=50))
    assert (Kind.JOINT_LIMIT, j2.line) in kinds(tight)


def test_an_unreachable_target_stops_the_run_on_its_line() -> None:
    r = preflight(
        "SERVO ON\nMOV P1\nMOV P9\nEND\n",
        "DEF POS P1=(400,0,300,180,0,180)(7,0)\nDEF POS P9=(900,0,300,180,0,180)(7,0)\n",
    )
    assert not r.finished and r.cycle_time is None
    errors_ = r.errors
    assert len(errors_) == 1 and errors_[0].kind is Kind.UNREACHABLE and errors_[0].line == 3
    assert "L2600" in errors_[0].message


def test_an_unreachable_point_the_run_never_reaches_is_still_reported() -> None:
    r = preflight(
        "SERVO ON\nIF M_IN(1) = 1 THEN MOV P9\nEND\n",
        "DEF POS P9=(900,0,300,180,0,180)(7,0)\n",
    )
    assert r.finished
    assert (Kind.UNREACHABLE, 2) in kinds(r) and not r.ok


def test_the_wrist_singularity_is_a_warning() -> None:
    r = preflight(
        "SERVO ON\nMOV P1\nEND\n", "DEF POS P1=(450,0,50,180,0,180)(7,0)\n", cell=Cell(None)
    )
    assert r.ok and (Kind.WRIST_SINGULARITY, 2) in kinds(r)


def test_the_shoulder_singularity_is_a_warning() -> None:
    r = preflight("SERVO ON\nMOV J1\nEND\n", "DEF JNT J1=(0,-70,120,0,90,0)\n", cell=Cell(None))
    assert (Kind.SHOULDER_SINGULARITY, 2) in kinds(r)


def test_a_run_that_waits_forever_is_a_warning_and_the_report_reads_well() -> None:
    r = preflight("SERVO ON\nWAIT M_IN(1) = 1\nEND\n")
    assert r.ok and not r.finished and (Kind.NOT_FINISHED, 2) in kinds(r)
    assert preflight("SERVO ON\nWAIT M_IN(1) = 1\nEND\n", inputs=[(1, 1)]).finished
    text = report_text(preflight(LOW, LOW_POINTS), "low.MB4")
    assert text.startswith("pre-flight of low.MB4 on the simulated RV-6S\ncycle time: ")
    assert "error: line 3: the move takes the tool 20.0 mm below the table" in text
    assert text.rstrip().endswith("fix the errors before running on the real arm")
    assert json.dumps(preflight(LOW, LOW_POINTS).to_json())  # serialisable for the web


def test_a_run_time_error_is_an_error_finding() -> None:
    r = preflight("SERVO ON\nM1 = M2\nEND\n")
    assert [(f.kind, f.line) for f in r.errors] == [(Kind.RUN_ERROR, 2)]
    with pytest.raises(DebugError):
        preflight("GOTO 99\n")


def test_cells_load_from_json_and_say_what_is_wrong() -> None:
    cell = Cell.from_json(
        '{"floor_z": -10, "boxes": [{"name": "jig", "min": [0, 0, 0], "max": [1, 2, 3]}]}'
    )
    assert cell == Cell(-10.0, (Box("jig", (0.0, 0.0, 0.0), (1.0, 2.0, 3.0)),))
    assert Cell.from_json(json.dumps(cell.to_json())) == cell
    assert Cell.from_json("{}") == Cell()
    for text, message in [
        ("[", "not JSON"),
        ('{"floor": 1}', "unknown field(s) floor"),
        ('{"floor_z": "low"}', 'floor_z must be a number (mm), got "low"'),
        ('{"boxes": [{"name": "a", "min": [0, 0], "max": [1, 1, 1]}]}', "box 'a': min must be"),
        ('{"boxes": [{"name": "a", "min": [2, 0, 0], "max": [1, 1, 1]}]}', "not be above max"),
        ('{"boxes": [{"name": "", "min": [0, 0, 0], "max": [1, 1, 1]}]}', "non-empty"),
    ]:
        with pytest.raises(CellError, match=message.replace("(", r"\(").replace(")", r"\)")):
            Cell.from_json(text)


coord = st.floats(min_value=-1000, max_value=1000, allow_nan=False)


@given(
    st.tuples(coord, coord, coord), st.tuples(coord, coord, coord), st.tuples(coord, coord, coord)
)
def test_a_box_contains_exactly_the_points_between_its_corners(
    a: tuple[float, float, float], b: tuple[float, float, float], p: tuple[float, float, float]
) -> None:
    lo = (min(a[0], b[0]), min(a[1], b[1]), min(a[2], b[2]))
    hi = (max(a[0], b[0]), max(a[1], b[1]), max(a[2], b[2]))
    box = Cell.from_json({"boxes": [{"name": "b", "min": list(lo), "max": list(hi)}]}).boxes[0]
    inside = all(lo[i] <= p[i] <= hi[i] for i in range(3))
    assert box.contains(*p) is inside
