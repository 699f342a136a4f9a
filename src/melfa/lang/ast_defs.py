"""The statements that declare: variables and their types (DEF INTE, DEF POS…), I/O names
(DEF IO), functions (DEF FN), pallets (DEF PLT), interrupts (DEF ACT, ACT n = …) and arrays
(DIM).

One family of the syntax tree (`melfa.lang.ast` re-exports every name here: import them from
there).
"""

from __future__ import annotations

import enum

from melfa.lang.ast_expr import Expr, JumpKind, JumpTarget, Name, Span
from melfa.lang.record import Record


class VarType(enum.Enum):
    INTE = "INTE"
    FLOAT = "FLOAT"
    DOUBLE = "DOUBLE"
    CHAR = "CHAR"
    POS = "POS"
    JNT = "JNT"


class DefVar(Record):
    """``DEF INTE a, b``; ``DEF POS P1 = (…)(7,0)`` gives one name a `value`."""

    type: VarType
    names: tuple[Name, ...]
    value: Expr | None
    span: Span


class IOType(enum.Enum):
    BIT = "BIT"
    BYTE = "BYTE"
    WORD = "WORD"
    INTEGER = "INTEGER"
    DWORD = "DWORD"


class DefIO(Record):
    """``DEF IO name = BIT|BYTE|WORD|INTEGER, bit [, mask]``."""

    name: Name
    io_type: IOType
    bit: Expr
    mask: Expr | None
    span: Span


class DefFn(Record):
    """``DEF FNname[(a, b)] = expr``; `name` includes the FN prefix, upper case."""

    name: Name
    params: tuple[Name, ...]
    body: Expr
    span: Span


class DefPlt(Record):
    """``DEF PLT no, start, endA, endB, [diag], countA, countB, dir`` (diagonal may be None)."""

    number: Expr
    start: Expr
    end_a: Expr
    end_b: Expr
    diagonal: Expr | None
    count_a: Expr
    count_b: Expr
    direction: Expr
    span: Span


class DefAct(Record):
    """``DEF ACT prio, condition GOTO|GOSUB target [, S|L]``."""

    priority: Expr
    condition: Expr
    kind: JumpKind
    target: JumpTarget
    mode: str | None
    span: Span


class DimArray(Record):
    name: Name
    sizes: tuple[Expr, ...]
    span: Span


class Dim(Record):
    """``DIM A(10), PT(3, 4)``."""

    arrays: tuple[DimArray, ...]
    span: Span


class ActSet(Record):
    """``ACT n = 1|0`` (``ACT 0 = …`` is the master switch)."""

    number: Expr
    value: Expr
    span: Span
