"""Run-time values of MELFA BASIC IV and their type rules.

Numbers are Python ``int`` (integer) and ``float`` (real): integer×integer stays integer,
``/`` always gives a real [S2 p.164]. Strings are ``str``. Positions and joints are frozen
dataclasses holding **radians** for A, B, C and joint angles, because that is what a
running program sees [melfa-basic-iv.md §2.3]; constants, points files and the arm API
use degrees, so conversion happens only at those boundaries (`from_degrees`,
`to_degrees`).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass, replace

from melfa.lang.ast import JOINT_ELEMENTS, POSITION_ELEMENTS
from melfa.lang.points import PointDef, PointKind
from melfa.sim.interp import errors

INT_MIN = -32768  # DEF INTE range [S1 DEF INTE]
INT_MAX = 32767
FLOAT_MAX = 1.70141e38  # DEF FLOAT range [S1 DEF FLOAT]
DEFAULT_FL1 = 7  # vertical arms: Right/Above/Non-flip [S2 p.146]
DEFAULT_FL2 = 0


@dataclass(frozen=True, slots=True)
class Position:
    """An XYZ position: X, Y, Z, L1, L2 in mm; A, B, C in **radians**; structure flags."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0
    l1: float = 0.0
    l2: float = 0.0
    fl1: int = DEFAULT_FL1
    fl2: int = DEFAULT_FL2

    @classmethod
    def from_degrees(
        cls,
        values: tuple[float, ...] | list[float],
        fl1: int = DEFAULT_FL1,
        fl2: int = DEFAULT_FL2,
    ) -> Position:
        """From controller units (mm, degrees), as written in constants and points files.

        >>> Position.from_degrees((1, 2, 3, 180, 0, 90)).c == math.pi / 2
        True
        """
        v = [float(x) for x in values] + [0.0] * (8 - len(values))
        return cls(
            v[0], v[1], v[2], math.radians(v[3]), math.radians(v[4]), math.radians(v[5]),
            v[6], v[7], int(fl1), int(fl2),
        )  # fmt: skip

    def to_degrees(self) -> tuple[float, float, float, float, float, float]:
        """X, Y, Z, A, B, C in mm and degrees (controller units)."""
        return (
            self.x, self.y, self.z,
            math.degrees(self.a), math.degrees(self.b), math.degrees(self.c),
        )  # fmt: skip

    def __str__(self) -> str:
        x, y, z, a, b, c = self.to_degrees()
        return f"({x:+.2f},{y:+.2f},{z:+.2f},{a:+.2f},{b:+.2f},{c:+.2f})({self.fl1},{self.fl2})"


@dataclass(frozen=True, slots=True)
class Joints:
    """A joint position: J1…J8 in **radians** (mm for linear axes, none on the RV-6S)."""

    values: tuple[float, ...]

    @classmethod
    def from_degrees(cls, values: tuple[float, ...] | list[float]) -> Joints:
        v = [float(x) for x in values] + [0.0] * (6 - len(values))
        return cls(tuple(math.radians(x) for x in v))

    def to_degrees(self) -> tuple[float, ...]:
        return tuple(math.degrees(x) for x in self.values)

    def __str__(self) -> str:
        return "(" + ",".join(f"{d:+.2f}" for d in self.to_degrees()) + ")"


Number = int | float
Value = int | float | str | Position | Joints


class VarType(enum.Enum):
    """Declared (or implied) type of a variable."""

    INTEGER = "INTE"
    FLOAT = "FLOAT"
    DOUBLE = "DOUBLE"
    NUMBER = (
        "NUMBER"  # undeclared M… variables: int or real as assigned [GUESS; doc §3 "treat as real"]
    )
    STRING = "CHAR"
    POSITION = "POS"
    JOINT = "JNT"
    IO = "IO"


_NUMBER_SUFFIXES = frozenset("%!#")  # integer, single, double type suffixes


def implied_type(name: str) -> VarType:
    """Type from the first letter (IV convention, melfa-basic-iv.md §2.1).

    Names that fit no rule are numeric, as in MELFA BASIC V (IV would want a DEF).

    >>> [implied_type(n).value for n in ("PA", "J_CURR", "CNAME$", "M1")]
    ['POS', 'JNT', 'CHAR', 'NUMBER']
    """
    if name.endswith("$"):
        return VarType.STRING
    if name[-1:] in _NUMBER_SUFFIXES:
        return VarType.NUMBER  # PATTERN% is a number whatever its first letter [S2 §4.3.6]
    first = name[:1].upper()
    if first == "P":
        return VarType.POSITION
    if first == "J":
        return VarType.JOINT
    return VarType.NUMBER


def type_name(value: Value) -> str:
    """The kind of a value in words, for error messages."""
    if isinstance(value, bool | int):
        return "integer"
    if isinstance(value, float):
        return "real"
    if isinstance(value, str):
        return "string"
    if isinstance(value, Position):
        return "position"
    return "joint"


def check_integer(value: int) -> int:
    if value < INT_MIN or value > INT_MAX:
        raise errors.RunError(
            errors.NUMERIC_OVERFLOW,
            f"integer overflow: {value} is outside {INT_MIN}..{INT_MAX}",
        )
    return value


def coerce(value: Value, vtype: VarType, name: str) -> Value:
    """Convert a value for storage in a variable of type `vtype`, or raise L4390-style."""
    if vtype is VarType.NUMBER or vtype is VarType.DOUBLE or vtype is VarType.IO:
        if isinstance(value, int | float):
            return value
    elif vtype is VarType.INTEGER:
        if isinstance(value, int | float):
            return check_integer(round_half_away(value))
    elif vtype is VarType.FLOAT:
        if isinstance(value, int | float):
            if abs(value) > FLOAT_MAX:
                raise errors.RunError(errors.NUMERIC_OVERFLOW, f"{name}: real overflow")
            return float(value)
    elif vtype is VarType.STRING:
        if isinstance(value, str):
            return value
    elif vtype is VarType.POSITION:
        if isinstance(value, Position):
            return value
    elif vtype is VarType.JOINT and isinstance(value, Joints):
        return value
    raise errors.RunError(
        errors.TYPE_COMBINATION,
        f"cannot store a {type_name(value)} in {name} ({vtype.value} variable)",
    )


def round_half_away(value: float) -> int:
    """CINT-style rounding (half away from zero), used where reals become integers.

    >>> round_half_away(2.5), round_half_away(-2.5), round_half_away(2.4)
    (3, -3, 2)
    """
    if isinstance(value, int):
        return value
    if not math.isfinite(value):
        raise errors.RunError(errors.NUMERIC_OVERFLOW, "number is not finite")
    return math.floor(abs(value) + 0.5) * (1 if value >= 0 else -1)


def truthy(value: Value) -> bool:
    """Conditions: true is non-zero [S1 WHILE]."""
    if isinstance(value, int | float):
        return value != 0
    raise errors.RunError(
        errors.TYPE_COMBINATION, f"a condition must be numeric, not a {type_name(value)}"
    )


# --- element access ------------------------------------------------------------------------


def get_element(value: Value, element: str) -> Number:
    """``P1.X`` (mm), ``P1.A`` (radians), ``P1.FL1``, ``J1.J3`` (radians)."""
    el = element.upper().lstrip(".")
    if isinstance(value, Position):
        if el in POSITION_ELEMENTS:
            result: Number = getattr(value, el.lower())
            return result
    elif isinstance(value, Joints) and el in JOINT_ELEMENTS:
        i = int(el[1:]) - 1
        return value.values[i] if i < len(value.values) else 0.0
    raise errors.RunError(errors.TYPE_COMBINATION, f"a {type_name(value)} has no element .{el}")


def set_element(value: Value, element: str, new: Value) -> Value:
    """A copy of `value` with one element changed (values are immutable)."""
    el = element.upper().lstrip(".")
    if not isinstance(new, int | float):
        raise errors.RunError(
            errors.TYPE_COMBINATION, f".{el} needs a number, not a {type_name(new)}"
        )
    if isinstance(value, Position) and el in POSITION_ELEMENTS:
        if el == "FL1":
            return replace(value, fl1=round_half_away(new))
        if el == "FL2":
            return replace(value, fl2=round_half_away(new))
        changes: dict[str, float] = {el.lower(): float(new)}
        return replace(value, **changes)  # type: ignore[arg-type]
    if isinstance(value, Joints) and el in JOINT_ELEMENTS:
        i = int(el[1:]) - 1
        vals = list(value.values) + [0.0] * max(0, i + 1 - len(value.values))
        vals[i] = float(new)
        return Joints(tuple(vals))
    raise errors.RunError(errors.TYPE_COMBINATION, f"a {type_name(value)} has no element .{el}")


def default_value(vtype: VarType) -> Value | None:
    """Value of a variable right after DEF: numbers 0 and strings empty [GUESS].

    Positions, joints and plain variables have no value until assigned (reading one is
    L3700), so a forgotten point is caught instead of moving to (0,0,0).
    """
    if vtype in (VarType.INTEGER, VarType.FLOAT, VarType.DOUBLE):
        return 0 if vtype is VarType.INTEGER else 0.0
    if vtype is VarType.STRING:
        return ""
    return None


def point_value(p: PointDef) -> Value:
    """A points-file entry as a program value (degrees in, radians inside)."""
    values = [v if v is not None else 0.0 for v in p.values]
    if p.kind is PointKind.JNT:
        return Joints.from_degrees(values)
    return Position.from_degrees(values, p.fl1 if p.fl1 is not None else 7, p.fl2 or 0)
