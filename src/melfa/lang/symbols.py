"""Symbol tables and expression types: what every name of a program is, and where it is made.

One pass over the program (`Symbols.collect`) records variables by kind (the first letter,
`DEF` types), arrays and their `DIM`, `DEF FN` functions, `DEF ACT` interrupts, and which
names are given a value. `Symbols.kind_of` types any expression with the language model's
facts (`melfa.lang.model`); it answers None when the kind is not certain, so the checker
only reports what is certainly wrong. Sections (§) are those of melfa-basic-iv.md.
"""

from __future__ import annotations

from collections.abc import Iterable

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.linetable import LineTable
from melfa.lang.model import FUNCTIONS, SYSTEM_VARIABLES, Kind
from melfa.lang.record import Record, field

_DEF_KIND = {
    A.VarType.INTE: Kind.NUM,
    A.VarType.FLOAT: Kind.NUM,
    A.VarType.DOUBLE: Kind.NUM,
    A.VarType.CHAR: Kind.STR,
    A.VarType.POS: Kind.POS,
    A.VarType.JNT: Kind.JNT,
}
_PREFIX_KIND = {"P": Kind.POS, "J": Kind.JNT, "M": Kind.NUM}
_EXTERNAL_PREFIX_KIND = {"P": Kind.POS, "J": Kind.JNT, "M": Kind.NUM, "C": Kind.STR}
_NUMBER_SUFFIXES = frozenset("%!#")  # integer, single and double precision [S2 §4.3.6]
_MAX_TYPE_DEPTH = 50  # long operator chains: give up typing rather than recurse deeply
_POSITIONAL = (Kind.POS, Kind.JNT)
# The operators whose result is a number whatever their operands: a tuple (compared by
# identity in C), not a set (Enum's __hash__ is a Python call).
_NUMERIC_OPS = (
    *(A.BinaryOp.EQ, A.BinaryOp.NE, A.BinaryOp.LT, A.BinaryOp.LE, A.BinaryOp.GT, A.BinaryOp.GE),
    *(A.BinaryOp.AND, A.BinaryOp.OR, A.BinaryOp.XOR),
)


class Made(Record):
    """Where a name is declared: line index, the name as written, its span."""

    line: int
    name: A.Name


class Symbols(Record, frozen=False):
    """The program's names. Keys are upper case (names ignore case)."""

    declared: dict[str, Kind] = field(default_factory=dict)  # DEF INTE/…/IO
    declared_at: dict[str, Made] = field(default_factory=dict)
    defined: set[str] = field(default_factory=set)  # given a value somewhere (or points)
    arrays: dict[str, tuple[Made, int]] = field(default_factory=dict)  # DIM: where, how many
    functions: dict[str, tuple[Made, int]] = field(default_factory=dict)  # DEF FN: where, args
    interrupts: dict[int, int] = field(default_factory=dict)  # DEF ACT priority -> line
    interrupt_targets: list[A.JumpTarget] = field(default_factory=list)  # DEF ACT … GOSUB
    duplicates: list[tuple[A.Name, Made, str]] = field(default_factory=list)  # (name, first, how)
    returns_with_mode: bool = False  # some RETURN 0|1 (an interrupt routine's end)
    # `kind_of_name`'s answers, each worked out once (the checker asks about every use of
    # every name); emptied when a DEF changes what a name is.
    kinds: dict[str, Kind | None] = field(default_factory=dict, compare=False)

    @classmethod
    def collect(
        cls, program: A.Program, points: Iterable[str], lines: LineTable | None = None
    ) -> Symbols:
        """The names of `program` (`lines`: its `LineTable`, if the caller has one)."""
        table = cls(defined={p.upper() for p in points})
        lines = lines or LineTable(program)
        statements = lines.statements
        for index in lines.having(_DEFINING):  # most lines (moves, commands) define nothing
            table.statement(index, statements[index])  # type: ignore[arg-type]  # not None
        return table

    def statement(self, index: int, stmt: A.Statement) -> None:
        defined = self.defined
        if isinstance(stmt, A.Assign):
            if not isinstance(stmt.target, A.Element):
                defined.add(target_name(stmt.target).name)
        elif isinstance(stmt, A.If):
            for branch in (stmt.then, stmt.else_):
                if isinstance(branch, A.Assign) and not isinstance(branch.target, A.Element):
                    defined.add(target_name(branch.target).name)
                elif isinstance(branch, A.Return):
                    self.returns_with_mode |= branch.mode is not None
        elif isinstance(stmt, A.Return):
            self.returns_with_mode |= stmt.mode is not None
        elif isinstance(stmt, A.DefVar):
            kind = _DEF_KIND[stmt.type]
            for n in stmt.names:
                self.declare(index, n, kind, f"DEF {stmt.type.value}")
                defined.add(n.name)
        elif isinstance(stmt, A.DefIO):
            self.declare(index, stmt.name, Kind.NUM, "DEF IO")
            defined.add(stmt.name.name)
        elif isinstance(stmt, A.Dim):
            for array in stmt.arrays:
                name = array.name
                first = self.arrays.get(name.name)
                if first is not None:
                    self.duplicates.append((name, first[0], "DIM"))
                else:
                    self.arrays[name.name] = (Made(index, name), len(array.sizes))
                defined.add(name.name)
        elif isinstance(stmt, A.DefFn):
            name = stmt.name
            first_fn = self.functions.get(name.name)
            if first_fn is not None:
                self.duplicates.append((name, first_fn[0], "DEF FN"))
            else:
                self.functions[name.name] = (Made(index, name), len(stmt.params))
        elif isinstance(stmt, A.DefAct):
            prio = stmt.priority
            if isinstance(prio, A.Number):
                self.interrupts.setdefault(int(prio.value), index)
            if stmt.kind is A.JumpKind.GOSUB:
                self.interrupt_targets.append(stmt.target)
        elif isinstance(stmt, A.For):
            defined.add(stmt.counter.name)
        elif isinstance(stmt, A.Input):
            defined.update(target_name(t).name for t in stmt.targets)
        elif isinstance(stmt, A.Fprm):
            defined.update(p.name for p in stmt.params)

    def declare(self, index: int, name: A.Name, kind: Kind, how: str) -> None:
        first = self.declared_at.get(name.name)
        if first is not None:
            self.duplicates.append((name, first, how))
            return
        self.declared[name.name] = kind
        self.declared_at[name.name] = Made(index, name)
        self.kinds.clear()

    # ----------------------------------------------------------------------------- types

    def kind_of_name(self, name: str) -> Kind | None:
        """A variable's kind: its DEF, else its first letter (§2.1); None when unknown."""
        kinds = self.kinds
        if name in kinds:
            return kinds[name]
        kind = kinds[name] = self._kind_of_name(name)
        return kind

    def _kind_of_name(self, name: str) -> Kind | None:
        declared = self.declared.get(name)
        if declared is not None:
            return declared
        last = name[-1:]
        if last == "$":
            return Kind.STR
        if last in _NUMBER_SUFFIXES:
            # A type suffix names a number (`DEF INTE PATTERN` then `PATTERN% = 3`),
            # whatever the first letter says [S2 §4.3.6].
            return Kind.NUM
        if len(name) > 1 and name[1] == "_":
            system = SYSTEM_VARIABLES.get(name)
            return system.kind if system is not None else _EXTERNAL_PREFIX_KIND.get(name[0])
        return _PREFIX_KIND.get(name[0])

    def kind_of(self, expr: A.Expr | None, depth: int = 0) -> Kind | None:
        """The kind of `expr` when it is certain, else None (§2.4, §5, §7)."""
        # The commonest classes first, each told by its class alone (no isinstance call:
        # the checker types every operand, move target and value of a program).
        if depth > _MAX_TYPE_DEPTH:
            return None
        cls = type(expr)
        if cls is A.Name:
            return self.kind_of_name(expr.name)  # type: ignore[union-attr,arg-type]
        if cls is A.Number:
            return Kind.NUM
        if cls is A.Binary:
            op = expr.op  # type: ignore[union-attr]
            if op in _NUMERIC_OPS:  # a comparison or AND, OR, XOR
                return Kind.NUM
            left = self.kind_of(expr.left, depth + 1)  # type: ignore[union-attr]
            right = self.kind_of(expr.right, depth + 1)  # type: ignore[union-attr]
            if left in _POSITIONAL and right is not Kind.STR:
                return left
            if left is Kind.NUM and right is Kind.NUM:
                return Kind.NUM
            if left is Kind.STR and right is Kind.STR and op is A.BinaryOp.ADD:
                return Kind.STR
            return None
        if cls is A.Index:
            return self.kind_of_name(expr.name.name)  # type: ignore[union-attr]
        if cls is A.Element:
            return Kind.NUM
        if cls is A.Unary:
            inner = self.kind_of(expr.operand, depth + 1)  # type: ignore[union-attr]
            return Kind.NUM if expr.op is A.UnaryOp.NOT else inner  # type: ignore[union-attr]
        if cls is A.Call:
            assert isinstance(expr, A.Call)
            if expr.user:
                return Kind.STR if expr.name.endswith("$") else None
            spec = FUNCTIONS.get(expr.name)
            return spec.result if spec is not None else None
        if cls is A.PositionLiteral:
            assert isinstance(expr, A.PositionLiteral)
            return Kind.POS if expr.flags is not None or len(expr.elements) > 8 else None
        if cls is A.String:
            return Kind.STR
        if cls is A.Pallet:
            return Kind.POS
        return None


# The statements `Symbols.statement` reads.
_DEFINING = frozenset(
    {A.Assign, A.DefVar, A.DefIO, A.Dim, A.DefFn, A.DefAct, A.Return, A.For, A.Input, A.Fprm}
    | {A.If}
)


def target_name(target: A.AssignTarget) -> A.Name:
    """The variable an assignment target names (``P1`` of ``P1.X``, ``M`` of ``M(3)``)."""
    while isinstance(target, A.Element):
        base = target.base
        if isinstance(base, (A.Name, A.Index)):
            target = base
        else:
            return A.Name("", target.span)
    return target if isinstance(target, A.Name) else target.name
