"""The grammar's two tables that both readers of a line use: the parser
(`melfa.lang.parser`) and its fast path for the commonest lines (`melfa.lang.fastline`).

`BINARY` gives each binary operator its precedence (the reference's table, §2.4) and node;
`COMMANDS` gives each statement that is a keyword and a plain argument list its node kind
and how many arguments it takes. One home, so the two readers cannot build different trees.
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.tokens import KEYWORDS

# Binary operator -> (precedence, BinaryOp); higher binds tighter. §2.4.
BINARY: dict[str, tuple[int, A.BinaryOp]] = {
    "XOR": (1, A.BinaryOp.XOR),
    "OR": (2, A.BinaryOp.OR),
    "AND": (3, A.BinaryOp.AND),
    # 4: NOT (prefix)
    "=": (5, A.BinaryOp.EQ),
    "<>": (5, A.BinaryOp.NE),
    "><": (5, A.BinaryOp.NE),
    "<": (5, A.BinaryOp.LT),
    "<=": (5, A.BinaryOp.LE),
    "=<": (5, A.BinaryOp.LE),
    ">": (5, A.BinaryOp.GT),
    ">=": (5, A.BinaryOp.GE),
    "=>": (5, A.BinaryOp.GE),
    "<<": (6, A.BinaryOp.SHL),
    ">>": (6, A.BinaryOp.SHR),
    "+": (7, A.BinaryOp.ADD),
    "-": (7, A.BinaryOp.SUB),
    "MOD": (8, A.BinaryOp.MOD),
    "\\": (9, A.BinaryOp.IDIV),
    "*": (10, A.BinaryOp.MUL),
    "/": (10, A.BinaryOp.DIV),
    # 11: unary + -
    "^": (12, A.BinaryOp.POW),
}

# Statements that are a keyword and a plain argument list: (min args, max args, empties ok).
COMMANDS: dict[str, tuple[A.CommandKind, int, int, bool]] = {
    "OVRD": (A.CommandKind.OVRD, 1, 3, False),
    "JOVRD": (A.CommandKind.JOVRD, 1, 1, False),
    "SPD": (A.CommandKind.SPD, 1, 1, False),
    "ACCEL": (A.CommandKind.ACCEL, 0, 6, True),
    "CNT": (A.CommandKind.CNT, 1, 3, True),
    "FINE": (A.CommandKind.FINE, 1, 2, False),
    "LOADSET": (A.CommandKind.LOADSET, 2, 2, False),
    "TORQ": (A.CommandKind.TORQ, 2, 2, False),
    "JRC": (A.CommandKind.JRC, 1, 2, False),
    "HOPEN": (A.CommandKind.HOPEN, 1, 4, False),
    "HCLOSE": (A.CommandKind.HCLOSE, 1, 4, False),
    "TOOL": (A.CommandKind.TOOL, 1, 1, False),
    "BASE": (A.CommandKind.BASE, 1, 1, False),
    "HLT": (A.CommandKind.HLT, 0, 0, False),
    "DLY": (A.CommandKind.DLY, 1, 1, False),
    "ERROR": (A.CommandKind.ERROR, 1, 1, False),
    "SKIP": (A.CommandKind.SKIP, 0, 0, False),
    "CALLP": (A.CommandKind.CALLP, 1, 17, False),
    "XLOAD": (A.CommandKind.XLOAD, 2, 2, False),
    "XRUN": (A.CommandKind.XRUN, 1, 3, False),
    "XSTP": (A.CommandKind.XSTP, 1, 1, False),
    "XRST": (A.CommandKind.XRST, 1, 1, False),
    "XCLR": (A.CommandKind.XCLR, 1, 1, False),
    "PRIORITY": (A.CommandKind.PRIORITY, 1, 2, False),
    "GETM": (A.CommandKind.GETM, 1, 1, False),
    # Plain RELM releases the mechanism: the reference's GETM example ends `60 RELM`
    # [S1 RELM, GETM].
    "RELM": (A.CommandKind.RELM, 0, 1, False),
    "CMPG": (A.CommandKind.CMPG, 1, 8, True),
    "CLR": (A.CommandKind.CLR, 1, 1, False),
    "CHRSRCH": (A.CommandKind.CHRSRCH, 2, 4, False),
}

assert set(BINARY) - {"MOD", "AND", "OR", "XOR"} <= {
    "=",
    "<>",
    "><",
    "<",
    "<=",
    "=<",
    ">",
    ">=",
    "=>",
    "<<",
    ">>",
    "+",
    "-",
    "\\",
    "*",
    "/",
    "^",
}
assert {"MOD", "AND", "OR", "XOR", "NOT"} <= KEYWORDS
