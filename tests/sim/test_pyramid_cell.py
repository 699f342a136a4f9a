"""The thesis's pyramid program in the thesis's bench (the shipped template cell): the six
blocks end as a 3-2-1 pyramid, each taken and let go on its line, with no pre-flight error."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from melfa.sim.debug.cell import CellError, Shape, Solid
from melfa.sim.debug.cell_templates import TEMPLATES, template, template_text
from melfa.sim.debug.cell_world import HandChange
from melfa.sim.debug.preflight import Kind, preflight

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PROGRAM = (EXAMPLES / "pyramid.MB4").read_text(encoding="utf-8")
POINTS = (EXAMPLES / "pyramid.POS").read_text(encoding="utf-8")


def line_of(text: str) -> int:
    return next(n for n, s in enumerate(PROGRAM.splitlines(), 1) if s.strip() == text)


def test_the_pyramid_stacks_the_blocks_in_the_thesis_bench() -> None:
    r = preflight(PROGRAM, POINTS, cell=template("thesis-bench"))
    assert r.finished and r.ok, [f.message for f in r.errors]
    assert r.collisions == ()
    # the stack is taken from the top: block 6 first, to the first place of the bottom row
    expected = {
        "block 6": (380, 150, 100, "bench"),
        "block 5": (434, 150, 100, "bench"),
        "block 4": (488, 150, 100, "bench"),
        "block 3": (407, 150, 125, "block 5"),  # over blocks 6 and 5
        "block 2": (461, 150, 125, "block 4"),  # over blocks 5 and 4
        "block 1": (434, 150, 150, "block 2"),  # over blocks 3 and 2
    }
    for part in r.parts:
        x, y, z, _ = expected[part.name]
        assert part.position == pytest.approx((x, y, z), abs=1e-6), part.name
        assert not part.held
    assert {p.name: p.on for p in r.parts}["block 1"] in ("block 2", "block 3")
    closes = [h for h in r.hands if h.change is HandChange.CLOSE]
    opens = [h for h in r.hands if h.change is HandChange.OPEN]
    assert [h.part for h in closes] == [f"block {k}" for k in range(6, 0, -1)]
    assert {h.line for h in closes} == {line_of("HCLOSE 1")}
    # the first HOPEN (before any block is taken) lets go of nothing
    assert opens[0].part is None and opens[0].line == line_of("HOPEN 1")
    assert [h.part for h in opens[1:]] == [h.part for h in closes]
    assert all(h.drop == pytest.approx(0.0, abs=1e-6) for h in opens[1:])
    assert [h.time for h in r.hands] == sorted(h.time for h in r.hands)


def test_templates_load_and_unknown_names_say_which_exist() -> None:
    assert TEMPLATES == ("thesis-bench",)
    cell = template()
    assert [p.name for p in cell.parts] == [f"block {k}" for k in range(1, 7)]
    assert template_text("thesis-bench").lstrip().startswith("{")
    with pytest.raises(CellError, match="templates: thesis-bench"):
        template("pyramid")


def test_a_post_between_the_stack_and_the_pyramid_is_hit_on_the_carrying_move() -> None:
    bench = template("thesis-bench")
    post = Solid("post", Shape.BOX, (40, 40, 400), (365, -50, 100))
    r = preflight(PROGRAM, POINTS, cell=replace(bench, fixtures=(*bench.fixtures, post)))
    hits = [c for c in r.collisions if c.obstacle == "post"]
    assert hits and not r.ok
    # the carrying move from the stack to the pyramid goes through it, each time
    carrying = [c for c in hits if c.line == line_of("MOV Pdest, -80")]
    assert len({c.move for c in carrying}) == 6
    assert all(PROGRAM.splitlines()[c.line - 1].lstrip()[:3] in ("MOV", "MVS") for c in hits)
    assert any(f.kind is Kind.COLLISION and "'post'" in f.message for f in r.errors)


def test_a_block_pushed_into_the_bench_is_a_collision_and_rests_on_it() -> None:
    pushed = PROGRAM.replace(
        "Pdest.Z = Pbase.Z + MALT * MFILA", "Pdest.Z = Pbase.Z + MALT * MFILA - 20"
    )
    r = preflight(pushed, POINTS, cell=template("thesis-bench"))
    hits = [c for c in r.collisions if c.carried and c.obstacle == "bench"]
    assert {c.body for c in hits} == {"block 6", "block 5", "block 4"}  # the bottom row
    assert {c.line for c in hits} == {line_of("MVS Pdest")}
    assert max(c.depth for c in hits) == pytest.approx(20.0, abs=0.5)
    assert any("the carried part 'block 6'" in f.message for f in r.errors)
    # let go 20 mm inside the bench, each block comes to rest on top of it
    ends = {p.name: p for p in r.parts}
    assert ends["block 6"].position[2] == pytest.approx(100.0) and ends["block 6"].on == "bench"
