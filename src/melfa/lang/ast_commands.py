"""The statements that are a keyword and plain operands: `Command` (``OVRD 50``,
``HOPEN 1``, ``DLY 0.5``, ``XRUN 2, "P1"``, told apart by `CommandKind`), the ON/OFF
switches (``SERVO ON``) and ``CMP``.

One family of the syntax tree (`melfa.lang.ast` re-exports every name here: import them from
there).
"""

from __future__ import annotations

import enum

from melfa.lang.ast_expr import Expr, Span
from melfa.lang.record import Record


class CommandKind(enum.Enum):
    """Statements that are a keyword followed by a plain argument list."""

    OVRD = "OVRD"
    JOVRD = "JOVRD"
    SPD = "SPD"
    ACCEL = "ACCEL"
    CNT = "CNT"
    FINE = "FINE"
    LOADSET = "LOADSET"
    TORQ = "TORQ"
    JRC = "JRC"
    HOPEN = "HOPEN"
    HCLOSE = "HCLOSE"
    TOOL = "TOOL"
    BASE = "BASE"
    END = "END"
    HLT = "HLT"
    DLY = "DLY"
    ERROR = "ERROR"
    SKIP = "SKIP"
    CALLP = "CALLP"
    XLOAD = "XLOAD"
    XRUN = "XRUN"
    XSTP = "XSTP"
    XRST = "XRST"
    XCLR = "XCLR"
    PRIORITY = "PRIORITY"
    GETM = "GETM"
    RELM = "RELM"
    CMPG = "CMPG"
    CLR = "CLR"
    RESET_ERR = "RESET ERR"
    CHRSRCH = "CHRSRCH"
    DEF_ARCH = "DEF ARCH"


class Command(Record):
    """A keyword and its arguments (omitted arguments, as in ``ACCEL ,50``, are None)."""

    kind: CommandKind
    args: tuple[Expr | None, ...]
    span: Span


class SwitchKind(enum.Enum):
    SERVO = "SERVO"
    PREC = "PREC"
    OADL = "OADL"


class Switch(Record):
    """``SERVO ON``, ``PREC OFF``, ``OADL ON``…; `args` are extra operands (mechanism no.)."""

    kind: SwitchKind
    on: bool
    args: tuple[Expr, ...]
    span: Span


class CmpMode(enum.Enum):
    JNT = "JNT"
    POS = "POS"
    TOOL = "TOOL"
    OFF = "OFF"


class Cmp(Record):
    """``CMP JNT|POS|TOOL, mask`` or ``CMP OFF``."""

    mode: CmpMode
    mask: Expr | None
    span: Span
