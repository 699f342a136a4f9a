"""Block structure: which NEXT closes which FOR, where IF, ELSE, CASE and BREAK jump.

The tree is flat (one statement per line); this module pairs the openers and closers in
text order and records every mismatch. The checker reports the mismatches; an interpreter
uses the tables to jump. All keys and values are indices into `Program.lines`.

Pairing is forgiving so that one mistake gives one finding: a closer that matches an
opener deeper in the stack closes the blocks above it (each reported as unclosed); a closer
with no opener at all is reported and ignored.
"""

from __future__ import annotations

import enum
from collections.abc import Iterable, Sequence
from itertools import compress
from operator import attrgetter

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.model import MAX_IF_DEPTH, MAX_LOOP_DEPTH
from melfa.lang.record import Record, field


class BlockKind(enum.Enum):
    FOR = "FOR"
    WHILE = "WHILE"
    IF = "IF"
    SELECT = "SELECT"


class BlockProblem(Record):
    """A structural mistake on line index `line` (rule name, controller code, fix hint)."""

    line: int
    span: A.Span
    rule: str
    code: str
    message: str
    suggestion: str | None = None


class BlockStructure(Record, frozen=False):
    """Jump tables for the interpreter and the problems for the checker.

    * ``for_next[for] = next`` and ``next_for[next] = (for, …)`` (a ``NEXT A, B`` closes two);
    * ``while_wend`` / ``wend_while``;
    * ``if_else[if] = else`` and ``if_endif[if] = endif`` for block IFs, ``else_endif``;
    * ``select_cases[select] = (case or default, …)`` in text order, ``select_end``,
      ``case_select[case or default or end select] = select``;
    * ``break_target[break] = line`` of the END SELECT (or NEXT/WEND) it leaves by, and
      ``break_block[break] = (kind, opener)``, the block it leaves. A one-line
      ``IF … THEN BREAK`` is a BREAK too.
    """

    for_next: dict[int, int] = field(default_factory=dict)
    next_for: dict[int, tuple[int, ...]] = field(default_factory=dict)
    while_wend: dict[int, int] = field(default_factory=dict)
    wend_while: dict[int, int] = field(default_factory=dict)
    if_else: dict[int, int] = field(default_factory=dict)
    if_endif: dict[int, int] = field(default_factory=dict)
    else_endif: dict[int, int] = field(default_factory=dict)
    select_cases: dict[int, tuple[int, ...]] = field(default_factory=dict)
    select_end: dict[int, int] = field(default_factory=dict)
    case_select: dict[int, int] = field(default_factory=dict)
    break_target: dict[int, int] = field(default_factory=dict)
    break_block: dict[int, tuple[BlockKind, int]] = field(default_factory=dict)
    problems: list[BlockProblem] = field(default_factory=list)


class _Open(Record, frozen=False):
    kind: BlockKind
    line: int
    span: A.Span
    counter: str | None = None
    counter_text: str = ""  # the counter as written, for messages
    else_line: int | None = None
    cases: list[int] = field(default_factory=list)
    breaks: list[int] = field(default_factory=list)


_CLOSER_NAMES = {
    BlockKind.FOR: ("FOR", "NEXT", "for-without-next", "L3230"),
    BlockKind.WHILE: ("WHILE", "WEND", "while-without-wend", "L3250"),
    BlockKind.IF: ("IF … THEN", "ENDIF", "if-without-endif", "L3252"),
    BlockKind.SELECT: ("SELECT", "END SELECT", "select-without-end", "L3254"),
}


def _keyword_span(span: A.Span, length: int) -> A.Span:
    return A.Span(span.line, span.column, span.line, span.column + length)


class _Matcher:
    def __init__(self) -> None:
        self.out = BlockStructure()
        self.stack: list[_Open] = []
        self.loop_depth = 0
        self.if_depth = 0

    def problem(
        self,
        line: int,
        span: A.Span,
        rule: str,
        code: str,
        message: str,
        suggestion: str | None = None,
    ) -> None:
        self.out.problems.append(BlockProblem(line, span, rule, code, message, suggestion))

    def push(self, block: _Open) -> None:
        self.stack.append(block)
        if block.kind in (BlockKind.FOR, BlockKind.WHILE):
            self.loop_depth += 1
            if self.loop_depth == MAX_LOOP_DEPTH + 1:
                self.problem(
                    block.line,
                    block.span,
                    "loop-nesting",
                    "L3240",
                    f"FOR/WHILE nested more than {MAX_LOOP_DEPTH} deep",
                    "Move the inner loops into a subroutine (GOSUB).",
                )
        elif block.kind is BlockKind.IF:
            self.if_depth += 1
            if self.if_depth == MAX_IF_DEPTH + 1:
                self.problem(
                    block.line,
                    block.span,
                    "if-nesting",
                    "L3253",
                    f"Block IF nested more than {MAX_IF_DEPTH} deep",
                    "Combine conditions with AND, or move the inner blocks into a GOSUB.",
                )

    def pop(self) -> _Open:
        block = self.stack.pop()
        if block.kind in (BlockKind.FOR, BlockKind.WHILE):
            self.loop_depth -= 1
        elif block.kind is BlockKind.IF:
            self.if_depth -= 1
        return block

    def unclosed(self, block: _Open) -> None:
        opener, closer, rule, code = _CLOSER_NAMES[block.kind]
        self.problem(
            block.line,
            block.span,
            rule,
            code,
            f"{opener} on this line is never closed",
            f"Add a matching {closer} where the block should end.",
        )

    def close(self, kind: BlockKind, line: int, span: A.Span) -> _Open | None:
        """Pop to the innermost open block of `kind`; None (and a problem) if there is none."""
        for depth in range(len(self.stack) - 1, -1, -1):
            if self.stack[depth].kind is kind:
                while len(self.stack) > depth + 1:
                    self.unclosed(self.pop())
                return self.pop()
        opener, closer, _, code = _CLOSER_NAMES[kind]
        rule = {
            BlockKind.FOR: "next-without-for",
            BlockKind.WHILE: "wend-without-while",
            BlockKind.IF: "endif-without-if",
            BlockKind.SELECT: "end-select-without-select",
        }[kind]
        self.problem(
            line,
            span,
            rule,
            code,
            f"{closer} without {opener}",
            f"Remove this {closer}, or add the {opener} it should close.",
        )
        return None

    def innermost(self, kind: BlockKind) -> _Open | None:
        for block in reversed(self.stack):
            if block.kind is kind:
                return block
        return None

    def line(self, index: int, stmt: A.Statement) -> None:
        if (
            type(stmt) is A.If
            and stmt.then is not None
            and type(stmt.then) is not A.Break
            and type(stmt.else_) is not A.Break
        ):
            return  # a one-line IF pairs with nothing, unless it BREAKs (the commonest IF)
        out = self.out
        span = stmt.span
        if isinstance(stmt, A.For):
            counter = stmt.counter
            self.push(
                _Open(BlockKind.FOR, index, _keyword_span(span, 3), counter.name, counter.written)
            )
        elif isinstance(stmt, A.Next):
            self.next(index, stmt)
        elif isinstance(stmt, A.While):
            self.push(_Open(BlockKind.WHILE, index, _keyword_span(span, 5)))
        elif isinstance(stmt, A.Wend):
            block = self.close(BlockKind.WHILE, index, span)
            if block is not None:
                out.while_wend[block.line] = index
                out.wend_while[index] = block.line
                self.resolve_breaks(block, index)
        elif isinstance(stmt, A.If) and stmt.is_block:
            self.push(_Open(BlockKind.IF, index, _keyword_span(span, 2)))
        elif isinstance(stmt, A.Else):
            top = self.stack[-1] if self.stack else None
            if top is not None and top.kind is BlockKind.IF and top.else_line is not None:
                self.problem(
                    index,
                    span,
                    "else-without-if",
                    "L3255",
                    f"Second ELSE in the IF block of line {top.span.line}",
                    "Remove one ELSE, or open a new IF … THEN block for it.",
                )
            elif top is None or top.kind is not BlockKind.IF:
                self.problem(
                    index,
                    span,
                    "else-without-if",
                    "L3255",
                    "ELSE without a block IF",
                    "Start the block with IF condition THEN (nothing after THEN), "
                    "or remove the ELSE.",
                )
            else:
                top.else_line = index
                out.if_else[top.line] = index
        elif isinstance(stmt, A.EndIf):
            block = self.close(BlockKind.IF, index, span)
            if block is not None:
                out.if_endif[block.line] = index
                if block.else_line is not None:
                    out.else_endif[block.else_line] = index
        elif isinstance(stmt, A.Select):
            if self.innermost(BlockKind.SELECT) is not None:
                self.problem(
                    index,
                    _keyword_span(span, 6),
                    "select-nested",
                    "L3254",
                    "SELECT cannot be nested inside another SELECT",
                    "Move the inner SELECT into a subroutine (GOSUB).",
                )
            self.push(_Open(BlockKind.SELECT, index, _keyword_span(span, 6)))
        elif isinstance(stmt, (A.Case, A.Default)):
            top = self.stack[-1] if self.stack else None
            if top is None or top.kind is not BlockKind.SELECT:
                word = "CASE" if isinstance(stmt, A.Case) else "DEFAULT"
                self.problem(
                    index,
                    span,
                    "case-outside-select",
                    "L3254",
                    f"{word} outside a SELECT (or inside a loop/IF within it)",
                    f"Move the {word} directly inside SELECT … END SELECT.",
                )
            else:
                top.cases.append(index)
                out.case_select[index] = top.line
        elif isinstance(stmt, A.EndSelect):
            block = self.close(BlockKind.SELECT, index, span)
            if block is not None:
                out.select_end[block.line] = index
                out.select_cases[block.line] = tuple(block.cases)
                out.case_select[index] = block.line
                self.resolve_breaks(block, index)
        elif isinstance(stmt, A.Break) or (
            isinstance(stmt, A.If)
            and (isinstance(stmt.then, A.Break) or isinstance(stmt.else_, A.Break))
        ):
            # BREAK leaves the innermost SELECT (or loop, in V programs).
            if not self.stack:
                self.problem(
                    index,
                    span,
                    "break-outside-block",
                    "L3254",
                    "BREAK outside SELECT or a loop",
                    "Remove the BREAK, or move it inside a SELECT or a loop.",
                )
            else:
                for block in reversed(self.stack):
                    if block.kind is not BlockKind.IF:
                        block.breaks.append(index)
                        out.break_block[index] = (block.kind, block.line)
                        break
                else:
                    self.problem(
                        index,
                        span,
                        "break-outside-block",
                        "L3254",
                        "BREAK outside SELECT or a loop",
                        "Remove the BREAK, or move it inside a SELECT or a loop.",
                    )

    def resolve_breaks(self, block: _Open, end_index: int) -> None:
        for b in block.breaks:
            self.out.break_target[b] = end_index

    def next(self, index: int, stmt: A.Next) -> None:
        names: tuple[str | None, ...] = tuple(c.name for c in stmt.counters) or (None,)
        closed: list[int] = []
        for k, name in enumerate(names):
            span = stmt.counters[k].span if stmt.counters else stmt.span
            written = stmt.counters[k].written if stmt.counters else ""
            top = self.stack[-1] if self.stack else None
            if top is not None and top.kind is BlockKind.FOR and name not in (None, top.counter):
                self.problem(
                    index,
                    span,
                    "next-mismatch",
                    "L3230",
                    f"NEXT {written} does not match FOR {top.counter_text} (line {top.span.line})",
                    f"Write NEXT {top.counter_text}.",
                )
                self.pop()
                closed.append(top.line)
                self.out.for_next[top.line] = index
                continue
            block = self.close(BlockKind.FOR, index, span)
            if block is None:
                break
            closed.append(block.line)
            self.out.for_next[block.line] = index
            self.resolve_breaks(block, index)
        if closed:
            self.out.next_for[index] = tuple(closed)

    def finish(self) -> BlockStructure:
        while self.stack:
            block = self.pop()
            self.unclosed(block)
            if block.kind is BlockKind.SELECT:
                self.out.select_cases[block.line] = tuple(block.cases)
        self.out.problems.sort(key=lambda p: (p.span.line, p.span.column))
        return self.out


def match_blocks(program: A.Program) -> BlockStructure:
    """Pair FOR/NEXT, WHILE/WEND, IF/ELSE/ENDIF and SELECT/CASE/END SELECT.

    >>> from melfa.lang.parser import parse
    >>> blocks = match_blocks(parse("FOR I=1 TO 3\\nWHILE M1\\nWEND\\nNEXT\\n"))
    >>> blocks.for_next, blocks.while_wend, blocks.problems
    ({0: 3}, {1: 2}, [])
    """
    return match_statements(tuple(map(_STATEMENT, program.lines)))


def match_statements(
    statements: Sequence[A.Statement | None], structural: Iterable[int] | None = None
) -> BlockStructure:
    """The same pairing over a list of statements (the interpreter's steps, in run order);
    indices are positions in `statements`. `structural`: the indices of the statements
    of the classes in `STRUCTURAL`, in order, when the caller has them already."""
    matcher = _Matcher()
    if structural is None:  # most lines (moves, commands) open or close nothing
        structural = compress(
            range(len(statements)), map(STRUCTURAL.__contains__, map(type, statements))
        )
    for index in structural:
        matcher.line(index, statements[index])  # type: ignore[arg-type]  # None is not structural
    return matcher.finish()


_STATEMENT = attrgetter("statement")
# The statements `_Matcher.line` reads (an IF only for its block or its BREAK).
STRUCTURAL = frozenset(
    {A.For, A.Next, A.While, A.Wend, A.If, A.Else, A.EndIf, A.Select, A.Case, A.Default}
    | {A.EndSelect, A.Break}
)
