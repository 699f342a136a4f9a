"""Cells an instructor starts from, shipped with melfa (``cells/<name>.json``).

``thesis-bench``: the thesis's bench and its six blocks, matching ``examples/pyramid.MB4``
and ``.POS``: a bench 100 mm high in front of the robot, six pucks (54 mm across, 25 mm
high) stacked at the pick place (350, -250), and a gripper that holds a puck's centre
107.5 mm below the flange (the program's positions are the flange's: it sets no TOOL).
"""

from __future__ import annotations

from importlib import resources

from melfa.sim.debug.cell import Cell, CellError

TEMPLATES = ("thesis-bench",)


def template_text(name: str) -> str:
    """The JSON text of template `name` (`CellError` for a name not in `TEMPLATES`)."""
    if name not in TEMPLATES:
        raise CellError(f"there is no cell template {name!r} (templates: {', '.join(TEMPLATES)})")
    return (resources.files("melfa.sim.debug") / "cells" / f"{name}.json").read_text("utf-8")


def template(name: str = "thesis-bench") -> Cell:
    """Template `name` as a `Cell`."""
    return Cell.from_json(template_text(name))
