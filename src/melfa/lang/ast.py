"""The typed syntax tree of a MELFA BASIC IV program: the one public home of its node names.

Node families (all frozen records, `melfa.lang.record`: dataclasses that cost nothing to
define, which matters for `melfa check`'s start-up; every node has a `span`, 1-based, end
exclusive). Each family is a module of its own; this module re-exports them all, so every part
reads the tree as ``from melfa.lang import ast as A`` and never needs to know which family a
node belongs to.

* **Program / Line** (here) — a program is a tuple of `Line`s, one per text line (blank and
  comment lines included, so line ``i`` of the tree is line ``i + 1`` of the text). A line has
  an optional step `number`, an optional `label` (``*NAME``, stored upper-case without ``*``),
  at most one `statement`, an optional trailing `comment`, and the parse `issues` found on
  it (each also referenced by the `Invalid…` node where parsing broke off).
* **Expressions** (`Expr`, `melfa.lang.ast_expr`) — literals (`Number`, `String`,
  `PositionLiteral` for both ``(x,y,z,a,b,c)(fl1,fl2)`` and joint constants ``(j1,…,j6)``),
  references (`Name`, `Index` for array elements and indexed system variables like
  ``M_IN(3)``, `Element` for ``P1.X``), `Call` (built-in or ``FN`` user functions), `Pallet`
  (``(PLT 1,5)``), `Unary`, `Binary`, and `InvalidExpr` where an expression could not be
  read; and the **jump targets** `LineRef` (``GOTO 100``) and `LabelRef` (``GOTO *LOOP``).
* **Statements** (`Statement`) — one class per statement shape: movement (`Move`, `ArcMove`,
  `ArchMove`, here: a move's WTH action is a statement), flow (`Goto`, `Gosub`, `OnJump`,
  `Return`, `Else`, `EndIf`, `For`, `Next`, `While`, `Wend`, `Select`, `Case`, `Break`,
  `Default`, `EndSelect`, `Wait`, `Fprm`: `melfa.lang.ast_flow`; `If` here, as its branch is
  a statement), definitions (`DefVar`, `DefIO`, `DefFn`, `DefPlt`, `DefAct`, `Dim`,
  `ActSet`: `melfa.lang.ast_defs`), assignments (`Assign`), I/O and files (`melfa.lang.ast_io`),
  and `Command` — the many statements that are a keyword plus arguments (``OVRD 50``,
  ``HOPEN 1``, ``DLY 0.5``, ``XRUN 2, "P1"``, ``DEF ARCH``), told apart by `CommandKind`, with
  the switches and CMP (`melfa.lang.ast_commands`). A statement that could not be parsed is an
  `InvalidStatement`: parsing never raises.

The nodes that hold a statement (a move's `Appended` action, an `If`'s branches) are defined
here with the `Statement` union, so the families import only `ast_expr` and never this module:
the tree's modules form no import cycle.

Block structure (which NEXT closes which FOR, where an IF jumps to) is not nested in the
tree, because the language is one statement per line; `melfa.lang.blocks.match_blocks`
computes it from the flat lines.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Iterator
from typing import TypeAlias

from melfa.lang.ast_commands import Cmp, CmpMode, Command, CommandKind, Switch, SwitchKind
from melfa.lang.ast_defs import (
    ActSet,
    DefAct,
    DefFn,
    DefIO,
    DefPlt,
    DefVar,
    Dim,
    DimArray,
    IOType,
    VarType,
)
from melfa.lang.ast_expr import (
    JOINT_ELEMENTS,
    POSITION_ELEMENTS,
    AssignTarget,
    Binary,
    BinaryOp,
    Call,
    Element,
    ElementKind,
    Expr,
    Index,
    InvalidExpr,
    JumpKind,
    JumpTarget,
    LabelRef,
    LineRef,
    Name,
    Number,
    NumberKind,
    Pallet,
    ParseIssue,
    PositionLiteral,
    Span,
    String,
    Unary,
    UnaryOp,
    constant_number,
)
from melfa.lang.ast_flow import (
    Break,
    Case,
    CaseKind,
    Default,
    Else,
    EndIf,
    EndSelect,
    For,
    Fprm,
    Gosub,
    Goto,
    Next,
    OnJump,
    Return,
    Select,
    Wait,
    Wend,
    While,
)
from melfa.lang.ast_io import (
    Assign,
    Close,
    ComControl,
    ComState,
    FileMode,
    Input,
    OnCom,
    Open,
    Print,
)
from melfa.lang.record import Record, field

__all__ = [
    "CHILD_FIELDS",
    "JOINT_ELEMENTS",
    "POSITION_ELEMENTS",
    "ActSet",
    "Appended",
    "ArcKind",
    "ArcMove",
    "ArchMove",
    "Assign",
    "AssignTarget",
    "Binary",
    "BinaryOp",
    "Break",
    "Call",
    "Case",
    "CaseKind",
    "Close",
    "Cmp",
    "CmpMode",
    "ComControl",
    "ComState",
    "Command",
    "CommandKind",
    "DefAct",
    "DefFn",
    "DefIO",
    "DefPlt",
    "DefVar",
    "Default",
    "Dim",
    "DimArray",
    "Element",
    "ElementKind",
    "Else",
    "EndIf",
    "EndSelect",
    "Expr",
    "FileMode",
    "For",
    "Fprm",
    "Gosub",
    "Goto",
    "IOType",
    "If",
    "Index",
    "Input",
    "InvalidExpr",
    "InvalidStatement",
    "JumpKind",
    "JumpTarget",
    "LabelRef",
    "Line",
    "LineRef",
    "Move",
    "MoveKind",
    "MoveType",
    "Name",
    "Next",
    "Number",
    "NumberKind",
    "OnCom",
    "OnJump",
    "Open",
    "Pallet",
    "ParseIssue",
    "PositionLiteral",
    "Print",
    "Program",
    "Return",
    "Select",
    "Span",
    "Statement",
    "String",
    "Switch",
    "SwitchKind",
    "Unary",
    "UnaryOp",
    "VarType",
    "Wait",
    "Wend",
    "While",
    "constant_number",
    "walk",
]


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


# -------------------------------------------------------------------- the IF, the union


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


# Node classes of the tree, and for each the names of its fields that hold nodes (a node,
# a tuple of nodes, or None), read from the annotations: `walk` (and `melfa.lang.relocate`)
# then never looks at strings, numbers, flags or enums. Every node class of the families is
# imported above (this module is their public home), so this module's names are all of them.
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
