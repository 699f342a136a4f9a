"""melfa.kin.reach: which points of a points file the RV-6S cannot take, and why."""

from __future__ import annotations

import pytest

from melfa.kin import HOME, fk
from melfa.kin.reach import ReachKind, reach_diagnostics, unreachable_points
from melfa.lang.diagnostics import Severity
from melfa.lang.points import PointDef
from melfa.lang.points_read import parse_points

DOWN = (180.0, 0.0, 180.0)  # hand pointing down


def pos(name: str, xyz: tuple[float, float, float], fl1: int = 7, fl2: int = 0) -> PointDef:
    return PointDef.pos(name, (*xyz, *DOWN), fl1, fl2)


def test_reachable_points_are_not_reported() -> None:
    home = fk(HOME)
    points = [
        pos("Phome", (400, 0, 450)),
        PointDef.pos("Pfk", (home.x, home.y, home.z, home.a, home.b, home.c), home.fl1),
        PointDef.jnt("Jhome", HOME),
        PointDef.jnt("Jedge", (170, 135, 166, 160, 120, 360)),  # every joint on its limit
    ]
    assert unreachable_points(points) == []


def test_too_far_says_how_far() -> None:
    [(name, reason)] = unreachable_points([pos("Pfar", (1200, 0, 450))])
    assert name == "Pfar"
    assert reason.startswith("is out of the RV-6S's reach (")
    assert "1130 mm from the shoulder" in reason and "610 mm" in reason


def test_wrong_flags_say_which_flags_would_work() -> None:
    # (400, 0, 450) hand down is an above-elbow, non-flip pose: FL1 = 3 (left) cannot take it.
    [(name, reason)] = unreachable_points([pos("Pflag", (400, 0, 450), fl1=3)])
    assert (name, reason) == ("Pflag", "is reachable only with flags (7,0), not (3,0)")


def test_a_joint_beyond_its_range() -> None:
    points = [PointDef.jnt("Jbad", (0, 140, 90, 0, 90, 0))]
    assert unreachable_points(points) == [("Jbad", "has J2 = 140°, beyond its limit -92…135°")]


def test_a_joint_pose_that_hits_the_arm() -> None:
    [(_, reason)] = unreachable_points([PointDef.jnt("Jfold", (0, -60, 40, 0, 90, 0))])
    assert reason.startswith("would make the arm hit itself (")


def test_points_with_omitted_elements_are_skipped() -> None:
    assert unreachable_points([PointDef.pos("Pgap", (5000, None, 0, 180, 0, 180))]) == []


TEXT = """' points
DEF POS Phome=(400,0,450,180,0,180)(7,0)
DEF POS Pfar=(1200,0,450,180,0,180)(7,0)
Pflag=(400,0,450,180,0,180)(3,0)
DEF JNT Jbad=(0,140,90,0,90,0)
"""


def test_diagnostics_sit_on_the_point_name() -> None:
    found = reach_diagnostics(parse_points(TEXT).points, TEXT)
    assert [(d.line, d.column, d.end_column, d.rule) for d in found] == [
        (3, 9, 13, ReachKind.OUT_OF_REACH.value),
        (4, 1, 6, ReachKind.NEEDS_FLAGS.value),
        (5, 9, 13, ReachKind.JOINT_LIMIT.value),
    ]
    assert all(d.severity is Severity.WARNING for d in found)
    assert found[0].message.startswith("Point Pfar is out of the RV-6S's reach")
    assert found[1].message == "Point Pflag is reachable only with flags (7,0), not (3,0)"
    assert found[2].message == "Point Jbad has J2 = 140°, beyond its limit -92…135°"
    assert all(d.suggestion and d.suggestion.endswith(".") for d in found)


@pytest.mark.parametrize("text", ["", "DEF POS Pfar=(1200,0,450,180,0,180)(7,0)"])
def test_diagnostics_stay_inside_the_text(text: str) -> None:
    points = [pos("Pfar", (1200, 0, 450))]
    for d in reach_diagnostics(points, text):  # line 0 (built in code): line 1 of the text
        assert d.line == 1 and 1 <= d.column <= d.end_column <= len(text) + 1
