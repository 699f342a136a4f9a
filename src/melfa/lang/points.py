"""Points files: the positions a program moves to, kept beside the `.MB4` program.

A points file is a project convention, not a Mitsubishi format (melfa-basic-iv.md §12):
one point per line, as the thesis's `.POS` files write them,

    DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)
    DEF JNT Jsafe=(0,0,90,0,90,0)

and, when uploading, the controller's own form with the `DEF POS ` prefix stripped,
`Pa=(…)(7,0)` (protocol.md §4.2 item 4).

Values are X, Y, Z in mm and A, B, C in **degrees** (optionally L1, L2), or J1…J6 (J7, J8)
in degrees. An element may be omitted (`(400,0,,180,0,180)`): it is kept as `None`.
Omitted structure flags default to the vertical arm's (7,0) [S2 p.146]. FL2 is a 32-bit
multi-rotation word, kept unsigned (−1 = &HFFFFFFFF).

This module holds the values only (`PointDef`, `PointsFile`), what the simulator, `kin`
and the grader take; `points_read.parse_points` reads a file into them and `points_write`
writes them back as text.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable, Iterator

from melfa.lang.diagnostics import Diagnostic
from melfa.lang.model import MAX_NAME_LENGTH as MODEL_MAX_NAME_LENGTH
from melfa.lang.record import Record, field

__all__ = [
    "DEFAULT_FL1",
    "DEFAULT_FL2",
    "FL2_MASK",
    "MAX_ELEMENTS",
    "MAX_NAME_LENGTH",
    "MIN_ELEMENTS",
    "PointDef",
    "PointKind",
    "PointsFile",
]

DEFAULT_FL1 = 7
"""Structure flag of a vertical arm when none is given: RIGHT/ABOVE/NONFLIP [S2 p.146]."""
DEFAULT_FL2 = 0
"""Multi-rotation word when none is given: every axis within ±180° [S2 p.146]."""
MAX_NAME_LENGTH = MODEL_MAX_NAME_LENGTH
"""IV names are at most 8 characters (L4300) [S3]; T/B position names too [S4 p.55]."""
MIN_ELEMENTS = 6
MAX_ELEMENTS = 8
"""X,Y,Z,A,B,C (+ L1, L2) or J1…J6 (+ J7, J8) [S2 p.145-146]."""
FL2_MASK = 0xFFFFFFFF


class PointKind(enum.Enum):
    """An XYZ position (`P…`, with flags) or a joint position (`J…`, no flags)."""

    POS = "POS"
    JNT = "JNT"


class PointDef(Record):
    """One named point.

    `values` holds 6 to 8 numbers in mm/degrees; `None` marks an omitted element.
    `fl1`/`fl2` are the structure flags of a POS point and `None` for a JNT point.
    `line` is where it was read from (1-based, 0 when built in code); it takes no part
    in equality, so a point read back from its own text compares equal.
    """

    name: str
    kind: PointKind
    values: tuple[float | None, ...]
    fl1: int | None = None
    fl2: int | None = None
    line: int = field(default=0, compare=False)

    def __post_init__(self) -> None:
        if not MIN_ELEMENTS <= len(self.values) <= MAX_ELEMENTS:
            raise ValueError(f"{self.name}: {len(self.values)} elements, expected 6 to 8")
        if self.kind is PointKind.JNT and (self.fl1 is not None or self.fl2 is not None):
            raise ValueError(f"{self.name}: joint positions have no structure flags")
        if self.kind is PointKind.POS and (self.fl1 is None or self.fl2 is None):
            raise ValueError(f"{self.name}: an XYZ position needs both structure flags")
        if self.fl2 is not None and not 0 <= self.fl2 <= FL2_MASK:
            raise ValueError(f"{self.name}: FL2 must be an unsigned 32-bit value")

    @classmethod
    def pos(
        cls,
        name: str,
        values: Iterable[float | None],
        fl1: int = DEFAULT_FL1,
        fl2: int = DEFAULT_FL2,
    ) -> PointDef:
        """An XYZ position: `PointDef.pos("Pa", (400, 0, 300, 180, 0, 180))`."""
        return cls(name, PointKind.POS, tuple(values), fl1, fl2 & FL2_MASK)

    @classmethod
    def jnt(cls, name: str, values: Iterable[float | None]) -> PointDef:
        """A joint position: `PointDef.jnt("Jsafe", (0, 0, 90, 0, 90, 0))`."""
        return cls(name, PointKind.JNT, tuple(values))

    @property
    def key(self) -> str:
        """The name as the controller sees it: names are case-insensitive [S2 §4.3.7(1)]."""
        return self.name.upper()


class PointsFile(Record):
    """What a points file holds: its points, and what is wrong with it.

    `names` lists every name a line tried to define, even when its value is broken, so
    that a program using the point is not flagged a second time for the same mistake.
    """

    points: tuple[PointDef, ...]
    diagnostics: tuple[Diagnostic, ...] = ()
    names: tuple[str, ...] = ()

    @property
    def has_errors(self) -> bool:
        return any(d.is_error for d in self.diagnostics)

    def get(self, name: str) -> PointDef | None:
        """The point called `name`, ignoring case as the controller does."""
        key = name.upper()
        return next((p for p in self.points if p.key == key), None)

    def __iter__(self) -> Iterator[PointDef]:
        return iter(self.points)

    def __len__(self) -> int:
        return len(self.points)
