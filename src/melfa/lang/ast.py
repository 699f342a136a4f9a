"""The typed syntax tree of a MELFA BASIC IV program.

Node families (all frozen records, `melfa.lang.record`: dataclasses that cost nothing to
define, which matters for `melfa check`'s start-up; every node has a `span`, 1-based, end
exclusive).

* **Program / Line** — a program is a tuple of `Line`s, one per text line (blank and comment
  lines included, so line ``i`` of the tree is line ``i + 1`` of the text). A line has an
  optional step `number`, an optional `label` (``*NAME``, stored upper-case without ``*``),
  at most one `statement`, an optional trailing `comment`, and the parse `issues` found on
  it (each also referenced by the `Invalid…` node where parsing broke off).
* **Expressions** (`Expr`) — literals (`Number`, `String`, `PositionLiteral` for both
  ``(x,y,z,a,b,c)(fl1,fl2)`` and joint constants ``(j1,…,j6)``), references (`Name`,
  `Index` for array elements and indexed system variables like ``M_IN(3)``, `Element` for
  ``P1.X``), `Call` (built-in or ``FN`` user functions), `Pallet` (``(PLT 1,5)``),
  `Unary`, `Binary`, and `InvalidExpr` where an expression could not be read.
* **Statements** — one class per statement shape: movement (`Move`, `MoveRelative`… see
  below), flow (`Goto`, `Gosub`, `OnJump`, `Return`, `If`, `Else`, `EndIf`, `For`, `Next`,
  `While`, `Wend`, `Select`, `Case`, `Break`, `Default`, `EndSelect`), definitions (`DefVar`,
  `DefIO`, `DefFn`, `DefPlt`, `DefAct`, `DefArch`, `Dim`), assignments (`Assign`), I/O and
  files, and `Command` — the many statements that are a keyword plus arguments (``OVRD 50``,
  ``HOPEN 1``, ``DLY 0.5``, ``XRUN 2, "P1"``), told apart by `CommandKind`. A statement that
  could not be parsed is an `InvalidStatement`: parsing never raises.
* **Jump targets** — `LineRef` (``GOTO 100``) and `LabelRef` (``GOTO *LOOP``).

Block structure (which NEXT closes which FOR, where an IF jumps to) is not nested in the
tree, because the language is one statement per line; `melfa.lang.blocks.match_blocks`
computes it from the flat lines.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Iterator
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


# ---------------------------------------------------------------------------- movement


class MoveType(Record):
    """``TYPE c1, c2`` after a move."""

    c1: Expr
    c2: Expr | None
    span: Span


class Appended(Record):
    """``WTH action`` or ``WTHIF condition, action`` after a move.

    `action` is an `Assign` (possibly with a DLY pulse), a HLT or SKIP `Command`, or an
    `InvalidStatement`.
    """

    condition: Expr | None
    action: Statement
    span: Span


class MoveKind(enum.Enum):
    MOV = "MOV"  # joint interpolation
    MVS = "MVS"  # linear interpolation


class Move(Record):
    """``MOV target[, close] [TYPE …] [WTH …]`` or ``MVS …``; ``MVS , d`` has no target."""

    kind: MoveKind
    target: Expr | None
    close: Expr | None
    type: MoveType | None
    appended: Appended | None
    span: Span


class ArcKind(enum.Enum):
    MVR = "MVR"  # start, via, end
    MVR2 = "MVR2"  # start, end, reference
    MVR3 = "MVR3"  # start, end, centre
    MVC = "MVC"  # start, via1, via2 (full circle)


class ArcMove(Record):
    """``MVR p1, p2, p3`` and the other arc/circle moves."""

    kind: ArcKind
    points: tuple[Expr, ...]
    type: MoveType | None
    appended: Appended | None
    span: Span


class ArchMove(Record):
    """``MVA target[, arch no]``."""

    target: Expr
    arch: Expr | None
    appended: Appended | None
    span: Span


# ------------------------------------------------------------------------ simple commands


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


# ---------------------------------------------------------------------------------- flow


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


class If(Record):
    """``IF cond THEN branch [ELSE branch]``; `then` None means a block IF (ends at ENDIF).

    A branch is a jump target (``THEN 100``, ``THEN *L``) or a statement (``THEN HOPEN 1``).
    """

    condition: Expr
    then: LineRef | LabelRef | Statement | None
    else_: LineRef | LabelRef | Statement | None
    span: Span

    @property
    def is_block(self) -> bool:
        return self.then is None


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


# --------------------------------------------------------------------------- definitions


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


# ------------------------------------------------------------------------- assignment, io

AssignTarget: TypeAlias = Name | Index | Element


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


class InvalidStatement(Record):
    """A statement that could not be parsed. `text` is its source; `issue` says why."""

    text: str
    issue: ParseIssue
    span: Span


Statement: TypeAlias = (
    Move
    | ArcMove
    | ArchMove
    | Command
    | Switch
    | Cmp
    | Goto
    | Gosub
    | OnJump
    | Return
    | If
    | Else
    | EndIf
    | For
    | Next
    | While
    | Wend
    | Select
    | Case
    | Break
    | Default
    | EndSelect
    | Wait
    | Fprm
    | DefVar
    | DefIO
    | DefFn
    | DefPlt
    | DefAct
    | Dim
    | ActSet
    | Assign
    | Open
    | Print
    | Input
    | Close
    | OnCom
    | ComControl
    | InvalidStatement
)

# ------------------------------------------------------------------------------- program


class Line(Record):
    """One text line. `statement` is None for blank, comment-only and label-only lines.

    `comment` is the comment text (``' …`` or ``REM …``) when the line has one.
    `label_text` is the label as written (no ``*``), for messages; no part in equality.
    """

    number: int | None
    label: str | None
    statement: Statement | None
    span: Span
    comment: str | None = None
    issues: tuple[ParseIssue, ...] = ()
    number_span: Span | None = None
    label_span: Span | None = None
    label_text: str | None = field(default=None, compare=False)


class Program(Record):
    """A whole program; `lines[i]` is text line ``i + 1``."""

    lines: tuple[Line, ...]

    @property
    def issues(self) -> tuple[ParseIssue, ...]:
        return tuple(issue for line in self.lines for issue in line.issues)


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


# Node classes of the tree, and for each the names of its fields that hold nodes (a node,
# a tuple of nodes, or None), read from the annotations: `walk` (and `melfa.lang.relocate`)
# then never looks at strings, numbers, flags or enums.
_NODE_TYPES: frozenset[type[Record]] = frozenset(  # built once, after every class above
    obj
    for obj in list(globals().values())
    if isinstance(obj, type) and issubclass(obj, Record) and obj not in (Record, ParseIssue)
)
_NODE_NAMES = {cls.__name__ for cls in _NODE_TYPES} | {
    "Expr",
    "Statement",
    "JumpTarget",
    "AssignTarget",
}
CHILD_FIELDS: dict[type, tuple[str, ...]] = {
    cls: tuple(
        name
        for name in cls.__record_fields__
        if _NODE_NAMES.intersection(re.findall(r"\w+", cls.__annotations__[name]))
    )
    for cls in _NODE_TYPES
}


def walk(node: object) -> Iterator[object]:
    """Every node under `node` (itself included), depth first."""
    stack = [node]
    children = CHILD_FIELDS
    pop, push = stack.pop, stack.append
    while stack:
        item = pop()
        fields = children.get(type(item))
        if fields is None:
            if type(item) is tuple:
                stack.extend(item)
            continue
        yield item
        for name in fields:
            value = getattr(item, name)
            if value is not None:
                push(value)
