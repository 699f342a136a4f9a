"""Checks on routines: how GOSUB and interrupt routines end, and jumps that leave them.

A mixin of the checker (`melfa.lang.check`), like `melfa.lang.check_names`. A routine runs
from its entry (a GOSUB or DEF ACT target) down to its RETURN, never on into another
routine's entry. Sections (§) are those of melfa-basic-iv.md.
"""

from __future__ import annotations

from bisect import bisect_left, bisect_right
from collections.abc import Iterable

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Severity
from melfa.lang.linetable import LineTable
from melfa.lang.reporter import Reporter
from melfa.lang.symbols import Symbols

E, W = Severity.ERROR, Severity.WARNING


class RoutineChecks(Reporter):
    """interrupt-return and goto-out-of-gosub; mixed into the checker's analyser."""

    program: A.Program
    symbols: Symbols
    table: LineTable
    _entries: frozenset[int] = frozenset()  # the lines routines start on (interrupt_returns)

    def interrupt_returns(self) -> None:
        """The routine DEF ACT … GOSUB jumps to ends with RETURN 0 or RETURN 1; a GOSUB
        routine with a plain RETURN (§4.5, [S1 RETURN])."""
        if not self.symbols.interrupt_targets and not self.symbols.returns_with_mode:
            return  # no interrupt routine and no RETURN 0|1: nothing to match
        lines = self.program.lines
        where = self.table.line_index

        def line_of(target: A.JumpTarget) -> int | None:
            key = target.name if isinstance(target, A.LabelRef) else target.number
            return where.get(key)

        def lines_of(targets: Iterable[A.JumpTarget]) -> set[int]:
            return {at for at in map(line_of, targets) if at is not None}

        interrupts = lines_of(self.symbols.interrupt_targets)
        subroutines: set[int] = set()
        for index in self.table.having(_CALLS):
            stmt = lines[index].statement
            if isinstance(stmt, A.Gosub):
                subroutines |= lines_of((stmt.target,))
            elif isinstance(stmt, A.OnJump) and stmt.kind is A.JumpKind.GOSUB:
                subroutines |= lines_of(stmt.targets)
        # A routine ends at its RETURN, but never runs on into another routine's entry: a
        # GOSUB used as a loop (`*MAIN … GOSUB *MAIN`) has no RETURN of its own, and the
        # RETURN 1 of an interrupt routine below it is not its end.
        self._entries = frozenset(interrupts | subroutines)
        for start in interrupts:
            ret = self._first_return(start)
            if ret is not None and ret.mode is None:
                self.add(
                    ret.span,
                    E,
                    "This RETURN ends an interrupt routine (DEF ACT … GOSUB), which needs "
                    "RETURN 0 (back to the interrupted line) or RETURN 1 (to the next line)",
                    "interrupt-return",
                    suggestion="Write RETURN 1 to go on with the next line, or RETURN 0 to "
                    "repeat the interrupted one.",
                )
        for start in subroutines - interrupts:
            ret = self._first_return(start)
            if ret is not None and ret.mode is not None:
                self.add(
                    ret.span,
                    E,
                    "RETURN 0 and RETURN 1 end interrupt routines; this routine is called "
                    "with GOSUB",
                    "interrupt-return",
                    suggestion="Write a plain RETURN.",
                )

    def gotos_leaving_routines(self) -> None:
        """A GOTO from inside a GOSUB routine to a line outside it: the RETURN never runs,
        so each pass leaves a return address on the stack until GOSUB's depth (about 800)
        is exceeded ("leaving a GOSUB with GOTO leaks stack", §4.5 [S1 RETURN, GOSUB]).
        A routine runs from its entry to its last RETURN before another routine's entry."""
        lines = self.program.lines
        where = self.table.line_index
        starts: set[int] = set()
        for index in self.table.having(_CALLS):
            stmt = lines[index].statement
            if isinstance(stmt, A.Gosub):
                targets: tuple[A.JumpTarget, ...] = (stmt.target,)
            elif isinstance(stmt, A.OnJump) and stmt.kind is A.JumpKind.GOSUB:
                targets = stmt.targets
            else:
                continue
            starts.update(at for at in (where.get(_key(t)) for t in targets) if at is not None)
        if not starts:
            return
        entries = starts | {
            at
            for at in (where.get(_key(t)) for t in self.symbols.interrupt_targets)
            if at is not None
        }
        # Indexes of the lines that return, that jump, and where routines start: each
        # routine is then found by bisection, not by walking the program once per routine.
        returns: list[int] = []
        jumps: list[tuple[int, tuple[A.JumpTarget, ...]]] = []
        statements = self.table.statements
        for i in self.table.having(_RETURNS_OR_JUMPS):
            stmt = statements[i]
            cls = type(stmt)
            if cls is A.Return:
                returns.append(i)
            elif cls is A.Goto or cls is A.If or cls is A.OnJump:
                if _returns(stmt):
                    returns.append(i)
                found = _gotos(stmt)
                if found:
                    jumps.append((i, found))
        jump_at = [i for i, _ in jumps]
        ordered = sorted(entries)
        for start in sorted(starts):
            after = ordered[bisect_right(ordered, start) :]
            limit = after[0] if after else len(lines)
            k = bisect_left(returns, limit) - 1
            if k < 0 or returns[k] < start:
                continue  # no RETURN: a GOSUB used as a loop, not a routine
            end = returns[k]
            line = lines[start]
            name = f"*{line.label_text}" if line.label_text else f"at step {line.number}"
            for _, targets in jumps[bisect_left(jump_at, start) : bisect_right(jump_at, end)]:
                for target in targets:
                    at = where.get(_key(target))
                    if at is None or start <= at <= end or _ends(lines, at):
                        continue
                    self.add(
                        target.span,
                        W,
                        f"This jump leaves the subroutine {name} before its RETURN: every "
                        "pass leaves a return address behind, and after about 800 the "
                        "program stops",
                        "goto-out-of-gosub",
                        suggestion="End the routine with RETURN and jump from where it was "
                        "called, or keep the jump inside the routine.",
                    )

    def _first_return(self, start: int) -> A.Return | None:
        entries = self._entries
        for index in range(start, len(self.program.lines)):
            if index != start and index in entries:
                return None
            stmt = self.program.lines[index].statement
            if isinstance(stmt, A.Return):
                return stmt
            if isinstance(stmt, A.If):
                for branch in (stmt.then, stmt.else_):
                    if isinstance(branch, A.Return):
                        return branch
        return None


# The statements that call a routine, and those that may return or jump (`_returns`, `_gotos`).
_CALLS = frozenset({A.Gosub, A.OnJump})
_RETURNS_OR_JUMPS = frozenset({A.Return, A.Goto, A.If, A.OnJump})


def _key(target: A.JumpTarget) -> str | int:
    return target.name if isinstance(target, A.LabelRef) else target.number


_STOPS = frozenset({A.CommandKind.END, A.CommandKind.ERROR})
# Tuples of classes, made once (``A | B`` would make a union object on every test).
_FLOW = (A.Goto, A.Gosub, A.OnJump, A.Return, A.If, A.For, A.While)
_TARGETS = (A.LabelRef, A.LineRef)


def _ends(lines: tuple[A.Line, ...], at: int) -> bool:
    """The code from line `at` stops the program (END, ERROR) before any jump: leaving a
    routine for it leaks nothing (``IF MPILA <= 0 THEN *EMPTY`` … ``ERROR 9100``)."""
    for line in lines[at:]:
        stmt = line.statement
        if isinstance(stmt, A.Command) and stmt.kind in _STOPS:
            return True
        if isinstance(stmt, _FLOW):
            return False
    return True


def _returns(stmt: A.Statement | None) -> bool:
    if isinstance(stmt, A.Return):
        return True
    return isinstance(stmt, A.If) and (
        isinstance(stmt.then, A.Return) or isinstance(stmt.else_, A.Return)
    )


def _gotos(stmt: A.Statement | None) -> tuple[A.JumpTarget, ...]:
    """Where a statement may jump with GOTO (not GOSUB, which comes back)."""
    if isinstance(stmt, A.Goto):
        return (stmt.target,)
    if isinstance(stmt, A.OnJump) and stmt.kind is A.JumpKind.GOTO:
        return stmt.targets
    if isinstance(stmt, A.If):
        found: list[A.JumpTarget] = []
        for branch in (stmt.then, stmt.else_):
            if isinstance(branch, _TARGETS):
                found.append(branch)
            elif isinstance(branch, A.Goto):
                found.append(branch.target)
        return tuple(found)
    return ()
