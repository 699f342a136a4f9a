"""The statements that set a variable or move data through a file or a port: assignment
(with a DLY pulse), OPEN, PRINT, INPUT, CLOSE, ON COM … GOSUB and COM ON/OFF/STOP.

One family of the syntax tree (`melfa.lang.ast` re-exports every name here: import them from
there).
"""

from __future__ import annotations

import enum

from melfa.lang.ast_expr import AssignTarget, Expr, JumpTarget, Span
from melfa.lang.record import Record


class Assign(Record):
    """``target = value`` with an optional pulse ``M_OUT(17)=1 DLY 0.5``."""

    target: AssignTarget
    value: Expr
    pulse: Expr | None
    span: Span


class FileMode(enum.Enum):
    INPUT = "INPUT"
    OUTPUT = "OUTPUT"
    APPEND = "APPEND"


class Open(Record):
    """``OPEN "COM1:" [FOR INPUT|OUTPUT|APPEND] AS [#]n``."""

    file: Expr
    mode: FileMode | None
    number: Expr
    span: Span


class Print(Record):
    """``PRINT #n, items`` (items separated by ``,`` or ``;``)."""

    channel: Expr | None
    items: tuple[Expr, ...]
    span: Span


class Input(Record):
    """``INPUT #n, targets``."""

    channel: Expr | None
    targets: tuple[AssignTarget, ...]
    span: Span


class Close(Record):
    """``CLOSE`` or ``CLOSE #1, #2``."""

    channels: tuple[Expr, ...]
    span: Span


class OnCom(Record):
    """``ON COM[(n)] GOSUB target``."""

    port: Expr | None
    target: JumpTarget
    span: Span


class ComState(enum.Enum):
    ON = "ON"
    OFF = "OFF"
    STOP = "STOP"


class ComControl(Record):
    """``COM[(n)] ON|OFF|STOP``."""

    port: Expr | None
    state: ComState
    span: Span
