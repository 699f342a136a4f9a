"""The values a statement is made of: expressions (literals, names, elements, calls,
pallets, operators), the places a jump goes (`LineRef`, `LabelRef`), and the `Span` and
`ParseIssue` every node carries.

One family of the syntax tree: the statements (`melfa.lang.ast_commands`, `ast_flow`,
`ast_defs`, `ast_io`, and `melfa.lang.ast` itself) hold these and nothing here holds a
statement, so the values sit below them all. Import the names from `melfa.lang.ast`, their one
public home, which re-exports them.
"""

from __future__ import annotations

import enum
from typing import NamedTuple, TypeAlias

from melfa.lang.record import Record, field


class Span(NamedTuple):
    """A source range: 1-based line and column, end exclusive.

    A NamedTuple rather than a dataclass: the parser makes one per token, and tuples are
    several times cheaper to build (the checker runs on every keystroke).
    """

    line: int
    column: int
    end_line: int
    end_column: int

    def to(self, other: Span) -> Span:
        """The range from the start of `self` to the end of `other`."""
        return Span(self.line, self.column, other.end_line, other.end_column)


class ParseIssue(Record):
    """A syntax problem found by the parser; `check()` turns it into a Diagnostic."""

    span: Span
    message: str
    rule: str
    code: str | None = "L4220"
    suggestion: str | None = None
    replacement: str | None = None
    """The word to write instead, when the fix is one word (``WHILE`` for ``WIHLE``)."""


# --------------------------------------------------------------------------- expressions


class NumberKind(enum.Enum):
    INTEGER = "integer"
    REAL = "real"
    HEX = "hex"
    BIN = "bin"


class Number(Record):
    """A numeric literal; `value` is an int for INTEGER/HEX/BIN, a float for REAL."""

    value: int | float
    kind: NumberKind
    text: str
    span: Span


class String(Record):
    """A string literal; `value` is without the quotes."""

    value: str
    span: Span


class Name(Record):
    """A variable (user or system). `name` is upper case (names are case-insensitive).

    `text` is the name as written (``Pa``), for messages; it takes no part in equality.
    """

    name: str
    span: Span
    text: str = field(default="", compare=False)

    @property
    def written(self) -> str:
        """The spelling to show a student: as written, else the upper-case name."""
        return self.text or self.name


class Index(Record):
    """``NAME(i[, j[, k]])``: an array element, or an indexed system variable (``M_IN(3)``)."""

    name: Name
    args: tuple[Expr, ...]
    span: Span


class ElementKind(enum.Enum):
    """The component after a dot."""

    X = "X"
    Y = "Y"
    Z = "Z"
    A = "A"
    B = "B"
    C = "C"
    L1 = "L1"
    L2 = "L2"
    FL1 = "FL1"
    FL2 = "FL2"
    J1 = "J1"
    J2 = "J2"
    J3 = "J3"
    J4 = "J4"
    J5 = "J5"
    J6 = "J6"
    J7 = "J7"
    J8 = "J8"


POSITION_ELEMENTS: tuple[str, ...] = tuple(
    k.value for k in ElementKind if not k.value.startswith("J")
)
"""A position's elements in the controller's order: X, Y, Z, A, B, C, L1, L2, FL1, FL2 (the
first six are the controller's `melfa.protocol.POSE_NAMES`; a test holds them together)."""
JOINT_ELEMENTS: tuple[str, ...] = tuple(k.value for k in ElementKind if k.value.startswith("J"))
"""A joint position's elements, J1 … J8 (the first six: `melfa.protocol.JOINT_NAMES`)."""


class Element(Record):
    """``P1.X``, ``J_CURR.J4``, ``P(3).FL1``."""

    base: Expr
    element: ElementKind
    span: Span


class PositionLiteral(Record):
    """``(x,y,z,a,b,c[,l1,l2])[(fl1,fl2)]`` or a joint constant ``(j1,…,j6[,j7,j8])``.

    Omitted elements (``(X,Y,Z,,,C)``, ``(,)``) are None. `flags` is None when the
    ``(fl1,fl2)`` part is absent. Whether a flagless constant is a position or a joint is
    decided by where it is used (the language does the same).
    """

    elements: tuple[Expr | None, ...]
    flags: tuple[Expr | None, ...] | None
    span: Span


class Call(Record):
    """A built-in function call (``SIN(M1)``, ``LEFT$(C1$,2)``) or a user ``FNxxx(...)``.

    `name` is upper case; `user` is True for ``FN`` functions defined with DEF FN.
    """

    name: str
    args: tuple[Expr, ...]
    user: bool
    span: Span


class Pallet(Record):
    """``(PLT n, k)``: grid point `index` of pallet `pallet`, a position."""

    pallet: Expr
    index: Expr
    span: Span


class UnaryOp(enum.Enum):
    PLUS = "+"
    MINUS = "-"
    NOT = "NOT"


class BinaryOp(enum.Enum):
    """Binary operators; `precedence` follows the reference table §2.4 (higher binds tighter)."""

    POW = "^"
    MUL = "*"
    DIV = "/"
    IDIV = "\\"
    MOD = "MOD"
    ADD = "+"
    SUB = "-"
    SHL = "<<"
    SHR = ">>"
    EQ = "="
    NE = "<>"
    LT = "<"
    LE = "<="
    GT = ">"
    GE = ">="
    AND = "AND"
    OR = "OR"
    XOR = "XOR"

    @property
    def is_comparison(self) -> bool:
        return self in _COMPARISON_OPS


_COMPARISON_OPS = frozenset(
    {BinaryOp.EQ, BinaryOp.NE, BinaryOp.LT, BinaryOp.LE, BinaryOp.GT, BinaryOp.GE}
)


class Unary(Record):
    op: UnaryOp
    operand: Expr
    span: Span


class Binary(Record):
    """`op_text` keeps the spelling written (``><`` is NE, ``=<`` is LE, ``=>`` is GE)."""

    op: BinaryOp
    left: Expr
    right: Expr
    span: Span
    op_text: str = ""


class InvalidExpr(Record):
    """Where an expression could not be read; `issue` says why."""

    issue: ParseIssue
    span: Span


Expr: TypeAlias = (
    Number
    | String
    | Name
    | Index
    | Element
    | PositionLiteral
    | Call
    | Pallet
    | Unary
    | Binary
    | InvalidExpr
)

# ------------------------------------------------------------------------------ targets


class LineRef(Record):
    """A jump to a step number: ``GOTO 100``."""

    number: int
    span: Span


class LabelRef(Record):
    """A jump to a label: ``GOTO *LOOP``; `name` is upper case without the ``*``.

    `text` is the label as written, without the ``*`` (no part in equality).
    """

    name: str
    span: Span
    text: str = field(default="", compare=False)

    @property
    def written(self) -> str:
        return self.text or self.name


JumpTarget: TypeAlias = LineRef | LabelRef


class JumpKind(enum.Enum):
    GOTO = "GOTO"
    GOSUB = "GOSUB"


AssignTarget: TypeAlias = Name | Index | Element


def constant_number(expr: Expr | None) -> int | float | None:
    """The value of a literal number, signed or not (``-5``, ``+&H10``); None for anything
    else. One reading of constants for the checker's ranges and for points files."""
    sign = 1
    while isinstance(expr, Unary) and expr.op is not UnaryOp.NOT:
        if expr.op is UnaryOp.MINUS:
            sign = -sign
        expr = expr.operand
    if isinstance(expr, Number):
        return sign * expr.value
    return None
