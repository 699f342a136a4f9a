"""Statements compiled to closures, with jumps and blocks resolved to step indices.

`Compiler.compile_program` orders the steps (ascending step numbers, as the controller
executes them [S2 §4.3.4]), matches FOR/NEXT, WHILE/WEND, IF/ELSE/ENDIF and
SELECT/CASE/END SELECT once, and turns every statement into a closure over the
interpreter's state. A structure error (a NEXT without FOR, a jump to a missing line) is
not a load failure: like the controller, the program stops with its error number when it
reaches that line. A line the controller refuses when the program is written to it is a
load failure, as the checker reports it: a syntax error (``SERVO ON (remark)``), a step
number outside 1…32767, a step longer than 127 characters. Of two lines with one step
number the last is kept, as the controller does [S2 §4.3.4].

The statement compilers live in one module per subject and are mixed in here:
`variables` (assignment, PRINT), `flow` (jumps, IF, loops, SELECT, WAIT), `motion_stmts`
(moves and robot commands), `definitions` (DEF …, DIM, ACT); block matching is in
`structure`. This module orders the steps and dispatches each statement to its compiler.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast
from melfa.lang.model import MAX_LINE_LENGTH, MAX_LINE_NUMBER
from melfa.sim.interp import errors
from melfa.sim.interp.definitions import DefinitionStatements
from melfa.sim.interp.errors import LINE_NUMBER_RANGE, STATEMENT_TOO_LONG
from melfa.sim.interp.flow import FlowStatements
from melfa.sim.interp.motion_stmts import MotionStatements
from melfa.sim.interp.state import Step
from melfa.sim.interp.stmt_base import Run, fail, nothing
from melfa.sim.interp.structure import match_blocks
from melfa.sim.interp.values import Value, VarType
from melfa.sim.interp.variables import VariableStatements


class Compiler(FlowStatements, MotionStatements, DefinitionStatements, VariableStatements):
    """Compiles a parsed program for one interpreter."""

    def compile_program(self, program: ast.Program, points: dict[str, Value]) -> list[Step]:
        lines = [ln for ln in program.lines if ln.number is not None or ln.label is not None
                 or ln.statement is not None]  # fmt: skip
        numbered = any(ln.number is not None for ln in lines)
        executable: list[ast.Line] = []
        for ln in lines:
            _refuse_at_load(ln)
            if numbered and ln.number is None:
                if ln.statement is not None and self._is_point(ln.statement):
                    self.take_point(ln.statement, points, ln.span.line)
                    continue
                if ln.statement is None:
                    continue
                raise errors.RunError(
                    errors.SYNTAX_ERROR,
                    f"text line {ln.span.line} has no step number",
                    line=ln.span.line,
                )
            executable.append(ln)
        if numbered:
            # One step a number, the last line written with it (the controller overwrites).
            last = {ln.number: ln for ln in executable}
            executable = sorted(last.values(), key=lambda ln: ln.number or 0)
        self.numbers = {}
        self.labels = {}
        for i, ln in enumerate(executable):
            if ln.number is not None:
                self.numbers.setdefault(ln.number, i)
            if ln.label is not None:
                if ln.label in self.labels:
                    raise errors.RunError(
                        4440, f"label *{ln.label} is defined twice", line=self._shown(ln)
                    )
                self.labels[ln.label] = i
        stmts = [ln.statement for ln in executable]
        self._stmts = stmts
        self._declare(stmts)
        self.structure = match_blocks(stmts)
        steps = []
        for i, ln in enumerate(executable):
            problem = self.structure.problems.get(i)
            if problem is not None:
                run = fail(*problem)
            elif ln.statement is None:
                run = nothing
            else:
                run = self.statement(ln.statement, i)
            steps.append(Step(self._shown(ln), run, ln.span.line, ln.label))
        return steps

    def take_point(self, stmt: ast.Statement, points: dict[str, Value], line: int) -> None:
        """A ``Name=(…)`` point definition (points file or unnumbered program line)."""
        target: ast.Name | None = None
        value: ast.Expr | None = None
        if isinstance(stmt, ast.Assign) and isinstance(stmt.target, ast.Name):
            target, value = stmt.target, stmt.value
        elif isinstance(stmt, ast.DefVar) and len(stmt.names) == 1 and stmt.value is not None:
            target, value = stmt.names[0], stmt.value
        if target is None or not isinstance(value, ast.PositionLiteral):
            raise errors.RunError(
                errors.SYNTAX_ERROR,
                f"position line {line} is not a point definition Name=(…)",
                line=line,
            )
        hint = VarType.JOINT if target.name.startswith("J") else VarType.POSITION
        points[target.name] = self.exprs.value(value, hint)()

    @staticmethod
    def _shown(ln: ast.Line) -> int:
        return ln.number if ln.number is not None else ln.span.line

    @staticmethod
    def _is_point(stmt: ast.Statement) -> bool:
        return (
            isinstance(stmt, ast.Assign)
            and isinstance(stmt.target, ast.Name)
            and isinstance(stmt.value, ast.PositionLiteral)
        )

    def compile_single(self, stmt: ast.Statement) -> Run:
        """One statement outside the program (EXEC); jumps are refused by the caller."""
        self._declare([stmt])
        return self.statement(stmt, self.st.current)

    def statement(self, s: ast.Statement, i: int) -> Run:
        method = _DISPATCH.get(type(s))
        if method is None:
            return fail(
                errors.NOT_SUPPORTED, f"{type(s).__name__} is not supported by the simulator"
            )
        return method(self, s, i)

    def _invalid(self, s: ast.InvalidStatement, i: int) -> Run:
        return fail(errors.SYNTAX_ERROR, f"syntax error: {s.issue.message}")

    def _refused(self, s: ast.Statement, i: int) -> Run:
        kind = type(s).__name__.upper()
        return fail(errors.NOT_SUPPORTED, f"{kind} is not supported by the simulator")

    def _noop(self, s: ast.Statement, i: int) -> Run:
        return nothing


def _refuse_at_load(ln: ast.Line) -> None:
    """A line the controller would not take: its syntax error, a step number out of range,
    a step too long (the checker's rules and numbers, `melfa.lang.check`)."""
    shown = ln.number if ln.number is not None else ln.span.line
    if ln.issues:
        issue = ln.issues[0]
        number = int(issue.code[1:]) if issue.code else errors.SYNTAX_ERROR
        raise errors.RunError(number, f"syntax error: {issue.message}", line=shown)
    if ln.number is not None and not 1 <= ln.number <= MAX_LINE_NUMBER:
        raise errors.RunError(
            LINE_NUMBER_RANGE, f"step number {ln.number} is out of range", line=shown
        )
    length = ln.span.end_column - 1
    if length > MAX_LINE_LENGTH:
        raise errors.RunError(
            STATEMENT_TOO_LONG,
            f"the step is {length} characters long; the controller allows {MAX_LINE_LENGTH}",
            line=shown,
        )


_DISPATCH: dict[type, Callable[..., Run]] = {
    ast.Assign: Compiler._assign,
    ast.Move: Compiler._move,
    ast.ArcMove: Compiler._arc,
    ast.ArchMove: Compiler._arch,
    ast.Command: Compiler._command,
    ast.Switch: Compiler._switch,
    ast.Cmp: Compiler._noop,
    ast.Goto: Compiler._goto,
    ast.Gosub: Compiler._gosub,
    ast.OnJump: Compiler._on_jump,
    ast.Return: Compiler._return,
    ast.If: Compiler._if,
    ast.Else: Compiler._else,
    ast.EndIf: Compiler._noop,
    ast.For: Compiler._for,
    ast.Next: Compiler._next,
    ast.While: Compiler._while,
    ast.Wend: Compiler._wend,
    ast.Select: Compiler._select,
    ast.Case: Compiler._noop,
    ast.Default: Compiler._noop,
    ast.Break: Compiler._break,
    ast.EndSelect: Compiler._noop,
    ast.Wait: Compiler._wait,
    ast.Fprm: Compiler._noop,
    ast.DefVar: Compiler._defvar,
    ast.DefIO: Compiler._defio,
    ast.DefFn: Compiler._deffn,
    ast.DefPlt: Compiler._defplt,
    ast.DefAct: Compiler._defact,
    ast.Dim: Compiler._dim,
    ast.ActSet: Compiler._actset,
    ast.Open: Compiler._noop,
    ast.Print: Compiler._print,
    ast.Close: Compiler._noop,
    ast.Input: Compiler._input,
    ast.OnCom: Compiler._refused,
    ast.ComControl: Compiler._refused,
    ast.InvalidStatement: Compiler._invalid,
}
