"""Built-in functions that need nothing but their arguments (melfa-basic-iv.md §5).

Trig is in radians. Functions that need the robot (PTOJ, JTOP, POSCQ) or the program
(pallets, user FN) live in the compiler. `IMPLEMENTATIONS` maps a name to how it computes;
which functions exist and how many arguments each takes is the language's knowledge, read
from `melfa.lang.model.FUNCTIONS`.
"""

from __future__ import annotations

import math
import random
from collections.abc import Callable, Sequence
from dataclasses import replace

from melfa.lang.ast import JOINT_ELEMENTS
from melfa.sim.interp import errors, posmath
from melfa.sim.interp.values import (
    Joints,
    Number,
    Position,
    Value,
    round_half_away,
    type_name,
)

Builtin = Callable[[Sequence[Value]], Value]


def _bad(message: str) -> errors.RunError:
    return errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, message)


def num(value: Value, fn: str) -> Number:
    if isinstance(value, int | float):
        return value
    raise errors.RunError(errors.TYPE_COMBINATION, f"{fn} needs a number, not a {type_name(value)}")


def integer(value: Value, fn: str) -> int:
    return round_half_away(num(value, fn))


def string(value: Value, fn: str) -> str:
    if isinstance(value, str):
        return value
    raise errors.RunError(errors.TYPE_COMBINATION, f"{fn} needs a string, not a {type_name(value)}")


def position(value: Value, fn: str) -> Position:
    if isinstance(value, Position):
        return value
    raise errors.RunError(
        errors.TYPE_COMBINATION, f"{fn} needs a position, not a {type_name(value)}"
    )


def format_number(value: Number) -> str:
    """How STR$ and PRINT show a number: integers plain, reals without trailing zeros.

    >>> format_number(10), format_number(2.5), format_number(1/3), format_number(3.0)
    ('10', '2.5', '0.333333', '3')
    """
    if isinstance(value, int):
        return str(value)
    return f"{value:.6g}"


def parse_number(text: str) -> Number:
    """VAL: decimal, ``&H…`` or ``&B…``; text that is not a number gives 0 (BASIC custom).

    >>> parse_number("12"), parse_number(" -2.5"), parse_number("&HFF"), parse_number("&B101")
    (12, -2.5, 255, 5)
    """
    t = text.strip().upper()
    try:
        if t.startswith("&H"):
            return int(t[2:], 16)
        if t.startswith("&B"):
            return int(t[2:], 2)
        if t and all(ch.isdigit() or ch in "+-" for ch in t):
            return int(t)
        return float(t)
    except ValueError:
        return 0


def _sqr(args: Sequence[Value]) -> Value:
    x = num(args[0], "SQR")
    if x < 0:
        raise _bad(f"SQR of a negative number ({x})")
    return math.sqrt(x)


def _ln(args: Sequence[Value]) -> Value:
    x = num(args[0], "LN")
    if x <= 0:
        raise _bad(f"LN needs a positive number, got {x}")
    return math.log(x)


def _log(args: Sequence[Value]) -> Value:
    x = num(args[0], "LOG")
    if x <= 0:
        raise _bad(f"LOG needs a positive number, got {x}")
    return math.log10(x)


def _exp(args: Sequence[Value]) -> Value:
    try:
        return math.exp(num(args[0], "EXP"))
    except OverflowError:
        raise errors.RunError(errors.NUMERIC_OVERFLOW, "EXP overflow") from None


def _abs(args: Sequence[Value]) -> Value:
    return abs(num(args[0], "ABS"))


def _sgn(args: Sequence[Value]) -> Value:
    x = num(args[0], "SGN")
    return (x > 0) - (x < 0)


def _fix(args: Sequence[Value]) -> Value:
    return math.trunc(num(args[0], "FIX"))


def _int(args: Sequence[Value]) -> Value:
    return math.floor(num(args[0], "INT"))


def _cint(args: Sequence[Value]) -> Value:
    return round_half_away(num(args[0], "CINT"))


def _max(args: Sequence[Value]) -> Value:
    return max(num(a, "MAX") for a in args)


def _min(args: Sequence[Value]) -> Value:
    return min(num(a, "MIN") for a in args)


def _trig(fn: Callable[[float], float], name: str) -> Builtin:
    def call(args: Sequence[Value]) -> Value:
        return fn(num(args[0], name))

    return call


def _tan(args: Sequence[Value]) -> Value:
    x = num(args[0], "TAN")
    if abs(math.cos(x)) < 1e-15:
        raise _bad("TAN is infinite at ±π/2")
    return math.tan(x)


def _atn2(args: Sequence[Value]) -> Value:
    return math.atan2(num(args[0], "ATN2"), num(args[1], "ATN2"))


def _len(args: Sequence[Value]) -> Value:
    return len(string(args[0], "LEN"))


def _asc(args: Sequence[Value]) -> Value:
    s = string(args[0], "ASC")
    if not s:
        raise _bad("ASC of an empty string")
    return ord(s[0])


def _val(args: Sequence[Value]) -> Value:
    return parse_number(string(args[0], "VAL"))


def _strpos(args: Sequence[Value]) -> Value:
    return string(args[0], "STRPOS").find(string(args[1], "STRPOS")) + 1


def _chr(args: Sequence[Value]) -> Value:
    n = integer(args[0], "CHR$")
    if not 0 <= n <= 255:
        raise _bad(f"CHR$ needs 0..255, got {n}")
    return chr(n)


def _left(args: Sequence[Value]) -> Value:
    n = integer(args[1], "LEFT$")
    if n < 0:
        raise _bad("LEFT$ length is negative")
    return string(args[0], "LEFT$")[:n]


def _right(args: Sequence[Value]) -> Value:
    n = integer(args[1], "RIGHT$")
    if n < 0:
        raise _bad("RIGHT$ length is negative")
    s = string(args[0], "RIGHT$")
    return s[len(s) - n :] if n else ""


def _mid(args: Sequence[Value]) -> Value:
    s = string(args[0], "MID$")
    start = integer(args[1], "MID$")
    if start < 1:
        raise _bad("MID$ start must be 1 or more")
    if len(args) > 2:
        n = integer(args[2], "MID$")
        if n < 0:
            raise _bad("MID$ length is negative")
        return s[start - 1 : start - 1 + n]
    return s[start - 1 :]


def _str(args: Sequence[Value]) -> Value:
    return format_number(num(args[0], "STR$"))


def _unsigned(n: int) -> int:
    """Negative integers as the controller's 16-bit (or 32-bit) two's complement."""
    if n >= 0:
        return n
    return n & 0xFFFF if n >= -32768 else n & 0xFFFFFFFF


def _radix(base: int, name: str) -> Builtin:
    def call(args: Sequence[Value]) -> Value:
        n = _unsigned(integer(args[0], name))
        text = format(n, "X" if base == 16 else "b")
        if len(args) > 1:
            digits = integer(args[1], name)
            if digits < 1:
                raise _bad(f"{name} digit count must be 1 or more")
            text = text[-digits:].rjust(digits, "0")
        return text

    return call


def _mirror(args: Sequence[Value]) -> Value:
    """MIRROR$: the bits of each character reversed."""
    return "".join(
        chr(int(format(ord(ch) & 0xFF, "08b")[::-1], 2)) for ch in string(args[0], "MIRROR$")
    )


def _deg(args: Sequence[Value]) -> Value:
    return math.degrees(num(args[0], "DEG"))


def _rad(args: Sequence[Value]) -> Value:
    return math.radians(num(args[0], "RAD"))


def _dist(args: Sequence[Value]) -> Value:
    return posmath.distance(position(args[0], "DIST"), position(args[1], "DIST"))


def _inv(args: Sequence[Value]) -> Value:
    return posmath.inverse(position(args[0], "INV"))


def _rdfl1(args: Sequence[Value]) -> Value:
    """RDFL1(P, k): "R"/"L" (k=0), "A"/"B" (k=1), "N"/"F" (k=2) [S1 RDFL1]."""
    p = position(args[0], "RDFL1")
    k = integer(args[1], "RDFL1")
    table = {0: (4, "R", "L"), 1: (2, "A", "B"), 2: (1, "N", "F")}
    if k not in table:
        raise _bad(f"RDFL1 flag index must be 0, 1 or 2, got {k}")
    bit, on, off = table[k]
    return on if p.fl1 & bit else off


def _setfl1(args: Sequence[Value]) -> Value:
    """SETFL1(P, "RAN"): P with FL1 built from the letters (or a number) [S1 SETFL1]."""
    p = position(args[0], "SETFL1")
    spec = args[1]
    if isinstance(spec, int | float):
        return _with(p, fl1=round_half_away(spec))
    letters = string(spec, "SETFL1").upper()
    fl1 = p.fl1
    for ch in letters:
        bit = {"R": 4, "L": 4, "A": 2, "B": 2, "N": 1, "F": 1}.get(ch)
        if bit is None:
            raise _bad(f"SETFL1 letter {ch!r} is not R, L, A, B, N or F")
        fl1 = fl1 | bit if ch in "RAN" else fl1 & ~bit
    return _with(p, fl1=fl1)


def _rdfl2(args: Sequence[Value]) -> Value:
    """RDFL2(P, axis): multi-rotation count −8…7 of one axis (4 bits each, J1 lowest)."""
    p = position(args[0], "RDFL2")
    axis = integer(args[1], "RDFL2")
    if not 1 <= axis <= len(JOINT_ELEMENTS):
        raise _bad(f"RDFL2 axis must be 1..{len(JOINT_ELEMENTS)}, got {axis}")
    nib = (p.fl2 >> (4 * (axis - 1))) & 0xF
    return nib - 16 if nib >= 8 else nib


def _setfl2(args: Sequence[Value]) -> Value:
    p = position(args[0], "SETFL2")
    axis = integer(args[1], "SETFL2")
    v = integer(args[2], "SETFL2")
    if not 1 <= axis <= len(JOINT_ELEMENTS) or not -8 <= v <= 7:
        raise _bad(f"SETFL2 needs axis 1..{len(JOINT_ELEMENTS)} and a count -8..7")
    shift = 4 * (axis - 1)
    fl2 = (p.fl2 & ~(0xF << shift) & 0xFFFFFFFF) | ((v & 0xF) << shift)
    return _with(p, fl2=fl2)


def _with(p: Position, **changes: int) -> Position:
    return replace(p, **changes)


def _posmid(args: Sequence[Value]) -> Value:
    """POSMID(P1, P2[, c1, c2]): the pose halfway between P1 and P2 (c1/c2 ignored)."""
    return posmath.interpolate(position(args[0], "POSMID"), position(args[1], "POSMID"), 0.5)


def _fram(args: Sequence[Value]) -> Value:
    try:
        return posmath.frame(*(position(a, "FRAM") for a in args[:3]))
    except ValueError as exc:
        raise _bad(f"FRAM: {exc}") from None


def _zone(args: Sequence[Value]) -> Value:
    p, p1, p2 = (position(a, "ZONE") for a in args[:3])
    return 1 if posmath.in_zone(p, p1, p2) else 0


def _setpos(args: Sequence[Value]) -> Value:
    """SETPOS(x, y, z, a, b, c): a position from numbers (A/B/C in radians, like elements)."""
    v = [float(num(a, "SETPOS")) for a in args] + [0.0] * (8 - len(args))
    return Position(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7])


def _setjnt(args: Sequence[Value]) -> Value:
    """SETJNT(j1, …, j6): a joint position from numbers (radians)."""
    return Joints(tuple(float(num(a, "SETJNT")) for a in args))


IMPLEMENTATIONS: dict[str, Builtin] = {
    "ABS": _abs,
    "ASC": _asc,
    "CINT": _cint,
    "DEG": _deg,
    "EXP": _exp,
    "FIX": _fix,
    "INT": _int,
    "LEN": _len,
    "LN": _ln,
    "LOG": _log,
    "MAX": _max,
    "MIN": _min,
    "RAD": _rad,
    "SGN": _sgn,
    "SQR": _sqr,
    "STRPOS": _strpos,
    "VAL": _val,
    "SIN": _trig(math.sin, "SIN"),
    "COS": _trig(math.cos, "COS"),
    "TAN": _tan,
    "ATN": _trig(math.atan, "ATN"),
    "ATN2": _atn2,
    "BIN$": _radix(2, "BIN$"),
    "CHR$": _chr,
    "HEX$": _radix(16, "HEX$"),
    "LEFT$": _left,
    "MID$": _mid,
    "MIRROR$": _mirror,
    "RIGHT$": _right,
    "STR$": _str,
    "DIST": _dist,
    "INV": _inv,
    "RDFL1": _rdfl1,
    "SETFL1": _setfl1,
    "RDFL2": _rdfl2,
    "SETFL2": _setfl2,
    "POSMID": _posmid,
    "FRAM": _fram,
    "ZONE": _zone,
    "SETPOS": _setpos,
    "SETJNT": _setjnt,
}


class Rnd:
    """RND(seed): a number in [0, 1); a non-zero seed restarts the sequence [S1 RND]."""

    def __init__(self, seed: int = 0) -> None:
        self._random = random.Random(seed)

    def __call__(self, args: Sequence[Value]) -> Value:
        seed = integer(args[0], "RND") if args else 0
        if seed:
            self._random.seed(seed)
        return self._random.random()
