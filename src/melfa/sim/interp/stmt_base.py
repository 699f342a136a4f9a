"""What every statement compiler shares: the closure types, small helpers and the state
they compile against.

The statement compilers are split by subject (`flow`, `motion_stmts`, `definitions`,
`variables`) and joined into `compiler.Compiler` as mixins; `CompilerBase` declares the
state they all read (the interpreter, the expression compiler, jump tables, block
structure) and the few methods they call across subjects, so each module type-checks on
its own.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast
from melfa.sim.interp import errors
from melfa.sim.interp.exprs import ExprCompiler, Thunk
from melfa.sim.interp.machine import Machine
from melfa.sim.interp.structure import Structure
from melfa.sim.interp.values import Value, round_half_away, type_name

Run = Callable[[], None]
Setter = Callable[[Value], None]


def fail(number: int, message: str) -> Run:
    def run() -> None:
        raise errors.RunError(number, message)

    return run


def number(value: Value, what: str) -> float:
    if isinstance(value, int | float):
        return float(value)
    raise errors.RunError(
        errors.TYPE_COMBINATION, f"{what} needs a number, not a {type_name(value)}"
    )


def integer(value: Value, what: str) -> int:
    return round_half_away(number(value, what))


def nothing() -> None:
    return None


def raiser(exc: errors.RunError) -> Run:
    def run() -> None:
        raise errors.RunError(exc.number, exc.message)

    return run


def refuse_set(message: str) -> Setter:
    def put(_v: Value) -> None:
        raise errors.RunError(errors.SYNTAX_ERROR, message)

    return put


class CompilerBase:
    """State shared by the statement compilers of one interpreter."""

    def __init__(self, it: Machine) -> None:
        self.it = it
        self.st = it.state
        self.exprs = ExprCompiler(it, self.io_reader)
        self.numbers: dict[int, int] = {}
        self.labels: dict[str, int] = {}
        self.structure = Structure()
        self.io_defs: dict[str, tuple[int, int, int | None]] = {}
        self._stmts: list[ast.Statement | None] = []

    # Implemented by the mixins `compiler.Compiler` is made of.
    def statement(self, s: ast.Statement, i: int) -> Run:
        raise NotImplementedError

    def setter(self, target: ast.AssignTarget, hint_value: ast.Expr | None = None) -> Setter:
        raise NotImplementedError

    def target(self, t: ast.LineRef | ast.LabelRef) -> int | errors.RunError:
        raise NotImplementedError

    def goto(self, t: ast.LineRef | ast.LabelRef) -> Run:
        raise NotImplementedError

    def io_reader(self, name: str) -> Thunk:
        raise NotImplementedError
