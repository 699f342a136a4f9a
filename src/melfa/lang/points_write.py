"""Writing points back as text (`melfa.lang.points`): the project's points file form
(`DEF POS Pa=(…)(7,0)`, one line a point) and the controller's upload form (`Pa=(…)(7,0)`,
protocol.md §4.2 item 4), two decimals as exports write them; `points_read` reads both back.
"""

from __future__ import annotations

from collections.abc import Iterable

from melfa.lang.points import PointDef, PointKind

__all__ = ["format_points", "format_value", "upload_lines"]


def format_value(value: float | None) -> str:
    """One element as exports write it: 2 decimals, empty when omitted, never `-0.00`.

    >>> format_value(417.605), format_value(-0.001), format_value(None)
    ('417.61', '0.00', '')
    """
    if value is None:
        return ""
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def _format_fl2(fl2: int) -> str:
    return "0" if fl2 == 0 else f"&H{fl2:08X}"


def _body(point: PointDef) -> str:
    values = ",".join(format_value(v) for v in point.values)
    if point.kind is PointKind.JNT:
        return f"{point.name}=({values})"
    assert point.fl1 is not None and point.fl2 is not None  # checked in PointDef
    return f"{point.name}=({values})({point.fl1},{_format_fl2(point.fl2)})"


def upload_lines(points: Iterable[PointDef]) -> list[str]:
    """The controller's form, one line per point: `Pa=(…)(7,0)` (protocol.md §4.2 item 4).

    >>> upload_lines([PointDef.pos("Pa", (400, 0, 300, 180, 0, 180))])
    ['Pa=(400.00,0.00,300.00,180.00,0.00,180.00)(7,0)']
    """
    return [_body(p) for p in points]


def format_points(points: Iterable[PointDef]) -> str:
    """A points file in the project's form: one `DEF POS`/`DEF JNT` line per point.

    >>> print(format_points([PointDef.jnt("Jsafe", (0, 0, 90, 0, 90, 0))]), end="")
    DEF JNT Jsafe=(0.00,0.00,90.00,0.00,90.00,0.00)
    """
    return "".join(f"DEF {p.kind.value} {_body(p)}\n" for p in points)
