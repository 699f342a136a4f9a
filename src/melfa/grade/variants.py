"""Per-student variants: a seed picks each group's offset, the same one every time.

A group (``[variants.pick]`` in assignment.toml) lists the cell's parts and the starter's
points that move together, and either offsets to pick from or ranges to shift within. The
seed (a student's number, their name, ``--variant 7``) is hashed with the group's name, so
two groups move independently and a seed always gives the same variant on every machine
(`random.Random` seeded with a text is stable across runs and Python versions 3.2+).
Checks that follow a group (``follows = "pick"``) move with it.
"""

from __future__ import annotations

import math
import random
from collections.abc import Mapping
from dataclasses import dataclass, field

from melfa.grade.model import VariantGroup, Vec3


@dataclass(frozen=True, slots=True)
class Variant:
    """The seed and each group's offset (mm, base frame)."""

    seed: str | None = None
    offsets: Mapping[str, Vec3] = field(default_factory=dict)

    def offset(self, group: str | None) -> Vec3:
        if group is None:
            return (0.0, 0.0, 0.0)
        return self.offsets.get(group, (0.0, 0.0, 0.0))

    def describe(self) -> str:
        """``pick: X +0, Y +40, Z +0 mm; place: …`` (what a student is told)."""
        return "; ".join(
            f"{name}: X {dx:+g}, Y {dy:+g}, Z {dz:+g} mm"
            for name, (dx, dy, dz) in sorted(self.offsets.items())
        )


NO_VARIANT = Variant()


def pick(groups: Mapping[str, VariantGroup], seed: str | int | None) -> Variant:
    """The variant of `seed` (None: every offset zero, the assignment as written).

    >>> from melfa.grade.model import VariantGroup
    >>> g = {"pick": VariantGroup(offsets=((0, 0, 0), (0, 40, 0), (0, -40, 0)))}
    >>> pick(g, 7) == pick(g, "7")
    True
    """
    if seed is None:
        return NO_VARIANT
    text = str(seed).strip()
    return Variant(text, {name: _offset(name, g, text) for name, g in groups.items()})


def _offset(name: str, group: VariantGroup, seed: str) -> Vec3:
    rng = random.Random(f"{seed}\x00{name}")
    if group.offsets:
        return tuple(float(v) for v in rng.choice(group.offsets))  # type: ignore[return-value]
    return (
        _stepped(rng, group.dx, group.step_mm),
        _stepped(rng, group.dy, group.step_mm),
        _stepped(rng, group.dz, group.step_mm),
    )


def _stepped(rng: random.Random, bounds: tuple[float, float], step: float) -> float:
    lo, hi = bounds
    steps = math.floor((hi - lo) / step + 1e-9)
    return lo + step * rng.randint(0, steps) if steps > 0 else lo


def shifted(xyz: tuple[float, ...], by: Vec3) -> tuple[float, ...]:
    """`xyz` (3 or 6 values) moved by `by`; A, B, C unchanged."""
    return (xyz[0] + by[0], xyz[1] + by[1], xyz[2] + by[2], *xyz[3:])
