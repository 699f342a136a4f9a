"""The statements that decide which step runs next: jumps (GOTO, GOSUB, ON … GOTO,
RETURN), the block words around an IF (ELSE, ENDIF), loops (FOR/NEXT, WHILE/WEND), SELECT
CASE, WAIT and CALLP's parameters (FPRM).

One family of the syntax tree (`melfa.lang.ast` re-exports every name here: import them from
there). The IF itself is in `melfa.lang.ast`: its branch may be any statement, and the union of
all statements is defined there.
"""

from __future__ import annotations

import enum

from melfa.lang.ast_expr import BinaryOp, Expr, JumpKind, JumpTarget, Name, Span
from melfa.lang.record import Record


class Goto(Record):
    target: JumpTarget
    span: Span


class Gosub(Record):
    target: JumpTarget
    span: Span


class OnJump(Record):
    """``ON expr GOTO|GOSUB t1, t2, …`` (1-based; out of range falls through)."""

    selector: Expr
    kind: JumpKind
    targets: tuple[JumpTarget, ...]
    span: Span


class Return(Record):
    """``RETURN`` (`mode` None) or the interrupt forms ``RETURN 0`` / ``RETURN 1``."""

    mode: Expr | None
    span: Span


class Else(Record):
    """A line holding only ``ELSE`` (block IF)."""

    span: Span


class EndIf(Record):
    span: Span


class For(Record):
    """``FOR counter = start TO end [STEP step]``."""

    counter: Name
    start: Expr
    end: Expr
    step: Expr | None
    span: Span


class Next(Record):
    """``NEXT`` or ``NEXT A, B`` (closes the loops of A then B)."""

    counters: tuple[Name, ...]
    span: Span


class While(Record):
    condition: Expr
    span: Span


class Wend(Record):
    span: Span


class Select(Record):
    subject: Expr
    span: Span


class CaseKind(enum.Enum):
    VALUE = "value"  # CASE 3
    IS = "is"  # CASE IS >= 3
    RANGE = "range"  # CASE 1 TO 5


class Case(Record):
    """``CASE v`` / ``CASE IS op v`` (`op` a comparison) / ``CASE lo TO hi`` (`high` set)."""

    kind: CaseKind
    value: Expr
    high: Expr | None
    op: BinaryOp | None
    span: Span


class Break(Record):
    span: Span


class Default(Record):
    span: Span


class EndSelect(Record):
    span: Span


class Wait(Record):
    """``WAIT condition`` (IV: ``WAIT M_IN(1)=1``)."""

    condition: Expr
    span: Span


class Fprm(Record):
    """``FPRM a, b, …``: the dummy parameters of a program called with CALLP."""

    params: tuple[Name, ...]
    span: Span
