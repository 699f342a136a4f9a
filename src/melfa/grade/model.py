"""What an assignment is: its `assignment.toml` as typed, validated records.

Every `[[checks]]` table is one of the `Check` models, chosen by its ``kind`` (a pydantic
discriminated union). Positions are the robot's base frame in mm (and degrees for A, B,
C), as in a points file. A check may name a variant group (``follows = "pick"``): its
positions then move with the group's offset for each student (`melfa.grade.variants`).
These records are the one home of the format; docs/assignments.md describes them and a
test keeps the two together.
"""

from __future__ import annotations

import datetime as dt
import enum
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from melfa.protocol.limits import HANDS, span_text

Vec3 = tuple[float, float, float]


class CheckKind(enum.StrEnum):
    """Every kind of check, by the name written in ``kind = "…"``."""

    FINAL_POSE = "final-pose"
    VISITS = "visits"
    PART_AT = "part-at"
    HAND = "hand"
    NO_COLLISION = "no-collision"
    CYCLE_TIME = "cycle-time"
    IO = "io"
    USES = "uses"
    AVOIDS = "avoids"
    NO_ERRORS = "no-errors"


class HandAction(enum.StrEnum):
    OPEN = "open"
    CLOSE = "close"


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _Check(_Strict):
    title: str | None = Field(None, description="what the student reads; a default is made")
    weight: float = Field(1.0, gt=0, description="its share of the score")


def _pose(values: tuple[float, ...]) -> tuple[float, ...]:
    if len(values) not in (3, 6):
        raise ValueError("a pose is [x, y, z] or [x, y, z, a, b, c] (mm, degrees)")
    return values


class FinalPose(_Check):
    """The tool (TCP) ends the run here; A, B, C are checked when given."""

    kind: Literal[CheckKind.FINAL_POSE]
    pose: tuple[float, ...]
    tolerance_mm: float = Field(1.0, gt=0)
    tolerance_deg: float = Field(1.0, gt=0)
    follows: str | None = None

    _valid_pose = field_validator("pose")(_pose)


class Visits(_Check):
    """The tool passes through every pose (in the order given when `in_order`)."""

    kind: Literal[CheckKind.VISITS]
    poses: tuple[tuple[float, ...], ...] = Field(min_length=1)
    tolerance_mm: float = Field(1.0, gt=0)
    in_order: bool = False
    follows: str | None = None

    @field_validator("poses")
    @classmethod
    def _valid_poses(cls, poses: tuple[tuple[float, ...], ...]) -> tuple[tuple[float, ...], ...]:
        for p in poses:
            _pose(p)
        return poses


class PartAt(_Check):
    """Part `part` of the cell ends the run at `position` (its reference point)."""

    kind: Literal[CheckKind.PART_AT]
    part: str = Field(min_length=1)
    position: Vec3
    tolerance_mm: float = Field(2.0, gt=0)
    follows: str | None = None


class Hand(_Check):
    """Hand `hand` opens (or closes) exactly at these tool positions, in this order.
    With `with_part` (the default) only a close that takes a part and an open that lets
    one go count (a HOPEN at the start, to be sure, is not a place)."""

    kind: Literal[CheckKind.HAND]
    action: HandAction
    at: tuple[Vec3, ...] = Field(min_length=1)
    hand: int = 1
    with_part: bool = True
    tolerance_mm: float = Field(2.0, gt=0)
    follows: str | None = None

    @field_validator("hand")
    @classmethod
    def _hand(cls, hand: int) -> int:
        if hand not in HANDS:
            raise ValueError(f"a hand number is {span_text(HANDS)}, got {hand}")
        return hand


class NoCollision(_Check):
    """No collision and no pre-flight error (unreachable, below the table, run error)."""

    kind: Literal[CheckKind.NO_COLLISION]


class CycleTime(_Check):
    """The run reaches END within `max_s` simulated seconds."""

    kind: Literal[CheckKind.CYCLE_TIME]
    max_s: float = Field(gt=0)


class Io(_Check):
    """With these inputs set (``M_IN``), the run ends with these outputs (``M_OUT``)."""

    kind: Literal[CheckKind.IO]
    inputs: dict[int, int] = Field(default_factory=dict)
    outputs: dict[int, int] = Field(min_length=1)

    @field_validator("inputs", "outputs")
    @classmethod
    def _bits(cls, bits: dict[int, int]) -> dict[int, int]:
        for bit, value in bits.items():
            if bit < 0:
                raise ValueError(f"bit numbers start at 0, got {bit}")
            if value not in (0, 1):
                raise ValueError(f"bit {bit}: a value is 0 or 1, got {value}")
        return bits


class Uses(_Check):
    """The program uses every one of these statements (``["GOSUB"]``)."""

    kind: Literal[CheckKind.USES]
    statements: tuple[str, ...] = Field(min_length=1)


class Avoids(_Check):
    """The program uses none of these statements (``["GOTO"]``)."""

    kind: Literal[CheckKind.AVOIDS]
    statements: tuple[str, ...] = Field(min_length=1)


class NoErrors(_Check):
    """`melfa check` finds no error in the program and its points."""

    kind: Literal[CheckKind.NO_ERRORS]


Check = Annotated[
    FinalPose | Visits | PartAt | Hand | NoCollision | CycleTime | Io | Uses | Avoids | NoErrors,
    Field(discriminator="kind"),
]
CHECK_MODELS: dict[CheckKind, type[_Check]] = {
    CheckKind.FINAL_POSE: FinalPose,
    CheckKind.VISITS: Visits,
    CheckKind.PART_AT: PartAt,
    CheckKind.HAND: Hand,
    CheckKind.NO_COLLISION: NoCollision,
    CheckKind.CYCLE_TIME: CycleTime,
    CheckKind.IO: Io,
    CheckKind.USES: Uses,
    CheckKind.AVOIDS: Avoids,
    CheckKind.NO_ERRORS: NoErrors,
}


class VariantGroup(_Strict):
    """Things that move together for each student: `offsets` (one picked by the seed) or
    ranges `dx`/`dy`/`dz` ([low, high] mm, in steps of `step_mm`)."""

    offsets: tuple[Vec3, ...] = ()
    dx: tuple[float, float] = (0.0, 0.0)
    dy: tuple[float, float] = (0.0, 0.0)
    dz: tuple[float, float] = (0.0, 0.0)
    step_mm: float = Field(1.0, gt=0)
    parts: tuple[str, ...] = Field((), description="the cell's parts and boxes that move")
    points: tuple[str, ...] = Field((), description="the starter points that move")

    @model_validator(mode="after")
    def _one_way(self) -> VariantGroup:
        ranged = any(r != (0.0, 0.0) for r in (self.dx, self.dy, self.dz))
        if self.offsets and ranged:
            raise ValueError("give offsets or dx/dy/dz ranges, not both")
        for name, (lo, hi) in (("dx", self.dx), ("dy", self.dy), ("dz", self.dz)):
            if lo > hi:
                raise ValueError(f"{name}: [low, high] with low ≤ high")
        return self


class AssignmentFile(_Strict):
    """``assignment.toml`` as written: the files it names are paths in the folder."""

    title: str = Field(min_length=1)
    statement: str = Field(description="the Markdown file of the statement")
    starter: str | None = Field(None, description="a starter program (.MB4)")
    starter_points: str | None = Field(None, description="its points (.POS)")
    cell: str | None = Field(None, description="the cell (JSON, as melfa debug --cell reads)")
    due: dt.datetime | dt.date | None = None
    attempts: int | None = Field(None, ge=1)
    max_time_s: float = Field(600.0, gt=0, description="simulated seconds a run may last")
    checks: tuple[Check, ...] = Field(min_length=1)
    variants: dict[str, VariantGroup] = Field(default_factory=dict)
