"""Expressions compiled to closures: operators, names, arrays, system variables, calls.

Each AST expression becomes a zero-argument function returning a value; the tree is walked
once at load time, so running ``M1 = M1 + 1`` costs two dictionary lookups and an add.
Conditions (IF, WHILE, WAIT, WTHIF, DEF ACT) are compiled with `cond`, where NOT/AND/OR/XOR
are logical; elsewhere they are bitwise on integers [melfa-basic-iv.md §2.4].
"""

from __future__ import annotations

import math
from collections.abc import Callable

from melfa.lang import ast
from melfa.lang import model as lang_model
from melfa.sim.interp import builtins, errors, posmath
from melfa.sim.interp.machine import Machine
from melfa.sim.interp.robot import robot_function
from melfa.sim.interp.values import (
    Joints,
    Position,
    Value,
    VarType,
    get_element,
    implied_type,
    round_half_away,
    truthy,
    type_name,
)

Thunk = Callable[[], Value]
Cond = Callable[[], bool]

TRUE_VALUE = 1
"""[GUESS] Value of a true comparison used as a number (``M1 = (A > B)``)."""


def type_error(message: str) -> errors.RunError:
    return errors.RunError(errors.TYPE_COMBINATION, message)


def undefined(name: str) -> errors.RunError:
    return errors.RunError(errors.UNDEFINED_VARIABLE, f"variable {name} has no value")


# --------------------------------------------------------------------------- operators


def _ints(a: Value, b: Value, op: str) -> tuple[int, int]:
    if isinstance(a, int | float) and isinstance(b, int | float):
        return round_half_away(a), round_half_away(b)
    raise type_error(f"{op} needs numbers, not {type_name(a)} and {type_name(b)}")


def op_add(a: Value, b: Value) -> Value:
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a + b
    if isinstance(a, str) and isinstance(b, str):
        return a + b
    if isinstance(a, Position) and isinstance(b, Position):
        return posmath.add(a, b)
    if isinstance(a, Joints) and isinstance(b, Joints):
        return posmath.joints_add(a, b)
    raise type_error(f"cannot add a {type_name(b)} to a {type_name(a)}")


def op_sub(a: Value, b: Value) -> Value:
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a - b
    if isinstance(a, Position) and isinstance(b, Position):
        return posmath.subtract(a, b)
    if isinstance(a, Joints) and isinstance(b, Joints):
        return posmath.joints_add(a, b, -1.0)
    raise type_error(f"cannot subtract a {type_name(b)} from a {type_name(a)}")


def op_mul(a: Value, b: Value) -> Value:
    if isinstance(a, int | float) and isinstance(b, int | float):
        return a * b
    if isinstance(a, Position):
        if isinstance(b, Position):
            return posmath.multiply(a, b)
        if isinstance(b, int | float):
            return posmath.scale(a, b)
    if isinstance(a, Joints) and isinstance(b, int | float):
        return posmath.joints_scale(a, b)
    # M1 * P1 is a description error on the controller [S2 p.163]
    raise type_error(f"cannot multiply a {type_name(a)} by a {type_name(b)}")


def _zero() -> errors.RunError:
    return errors.RunError(errors.DIVISION_BY_ZERO, "division by zero")


def op_div(a: Value, b: Value) -> Value:
    if isinstance(a, int | float) and isinstance(b, int | float):
        if b == 0:
            raise _zero()
        return a / b  # integer/integer is real [S2 p.164]
    if isinstance(a, Position):
        if isinstance(b, Position):
            return posmath.divide(a, b)
        if isinstance(b, int | float):
            if b == 0:
                raise _zero()
            return posmath.scale(a, 1.0 / b)
    if isinstance(a, Joints) and isinstance(b, int | float):
        if b == 0:
            raise _zero()
        return posmath.joints_scale(a, 1.0 / b)
    raise type_error(f"cannot divide a {type_name(a)} by a {type_name(b)}")


def op_idiv(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "\\")
    if y == 0:
        raise _zero()
    q = abs(x) // abs(y)
    return q if (x >= 0) == (y >= 0) else -q


def op_mod(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "MOD")
    if y == 0:
        raise _zero()
    return int(math.fmod(x, y))  # sign of the dividend, as in BASIC


def op_pow(a: Value, b: Value) -> Value:
    # [S2 p.164] real operands of ^ are rounded to integers first
    x, y = _ints(a, b, "^")
    if y < 0:
        if x == 0:
            raise _zero()
        return float(x) ** y
    result: int = x**y
    return result


def op_shl(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "<<")
    return x << y if y >= 0 else x >> -y


def op_shr(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, ">>")
    return x >> y if y >= 0 else x << -y


def op_and(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "AND")
    return x & y


def op_or(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "OR")
    return x | y


def op_xor(a: Value, b: Value) -> Value:
    x, y = _ints(a, b, "XOR")
    return x ^ y


def compare(op: ast.BinaryOp, a: Value, b: Value) -> bool:
    if (isinstance(a, int | float) and isinstance(b, int | float)) or (
        isinstance(a, str) and isinstance(b, str)
    ):
        if op is ast.BinaryOp.EQ:
            return a == b
        if op is ast.BinaryOp.NE:
            return a != b
        if op is ast.BinaryOp.LT:
            return a < b  # type: ignore[operator]
        if op is ast.BinaryOp.LE:
            return a <= b  # type: ignore[operator]
        if op is ast.BinaryOp.GT:
            return a > b  # type: ignore[operator]
        return a >= b  # type: ignore[operator]
    if type(a) is type(b) and op in (ast.BinaryOp.EQ, ast.BinaryOp.NE):
        return (a == b) == (op is ast.BinaryOp.EQ)
    raise type_error(f"cannot compare a {type_name(a)} with a {type_name(b)}")


ARITHMETIC: dict[ast.BinaryOp, Callable[[Value, Value], Value]] = {
    ast.BinaryOp.ADD: op_add,
    ast.BinaryOp.SUB: op_sub,
    ast.BinaryOp.MUL: op_mul,
    ast.BinaryOp.DIV: op_div,
    ast.BinaryOp.IDIV: op_idiv,
    ast.BinaryOp.MOD: op_mod,
    ast.BinaryOp.POW: op_pow,
    ast.BinaryOp.SHL: op_shl,
    ast.BinaryOp.SHR: op_shr,
    ast.BinaryOp.AND: op_and,
    ast.BinaryOp.OR: op_or,
    ast.BinaryOp.XOR: op_xor,
}

LOGICAL = (ast.BinaryOp.AND, ast.BinaryOp.OR, ast.BinaryOp.XOR)


def static_type(expr: ast.Expr) -> VarType | None:
    """What a name-based look at an expression says its type is (None: unknown)."""
    if isinstance(expr, ast.Name):
        return implied_type(expr.name)
    if isinstance(expr, ast.Index):
        return implied_type(expr.name.name)
    if isinstance(expr, ast.Binary) and expr.op in (ast.BinaryOp.ADD, ast.BinaryOp.SUB):
        return static_type(expr.left) or static_type(expr.right)
    if isinstance(expr, ast.Binary) and expr.op in (ast.BinaryOp.MUL, ast.BinaryOp.DIV):
        return static_type(expr.left)
    if isinstance(expr, ast.PositionLiteral):
        return VarType.POSITION if expr.flags is not None else None
    return None


# --------------------------------------------------------------------------- compiler


class ExprCompiler:
    """Turns expressions into closures bound to one interpreter's variables."""

    def __init__(self, it: Machine, io_reader: Callable[[str], Thunk]) -> None:
        self.it = it
        self.st = it.state
        self.io_reader = io_reader
        """Reads a DEF IO variable (the statement compilers know the DEF IO table)."""

    # -- values --------------------------------------------------------------------------
    def value(self, e: ast.Expr, hint: VarType | None = None) -> Thunk:
        """A closure computing `e`; `hint` decides whether a flagless ``(…)`` is a joint."""
        if isinstance(e, ast.Number):
            v: Value = e.value
            return lambda: v
        if isinstance(e, ast.String):
            s = e.value
            return lambda: s
        if isinstance(e, ast.Name):
            return self.name(e.name)
        if isinstance(e, ast.Binary):
            return self.binary(e, hint)
        if isinstance(e, ast.Unary):
            return self.unary(e, hint)
        if isinstance(e, ast.Element):
            return self.element(e)
        if isinstance(e, ast.Index):
            return self.index(e)
        if isinstance(e, ast.PositionLiteral):
            return self.literal(e, hint)
        if isinstance(e, ast.Call):
            return self.call(e)
        if isinstance(e, ast.Pallet):
            return self.pallet(e)
        message = e.issue.message

        def invalid() -> Value:
            raise errors.RunError(errors.SYNTAX_ERROR, message)

        return invalid

    def name(self, name: str) -> Thunk:
        sysvar = self.it.sysvars.getter(name, ())
        if sysvar is not None:
            return sysvar
        if self.st.types.get(name) is VarType.IO:
            return self.io_reader(name)
        store = self.st.vars

        def read() -> Value:
            try:
                return store[name]
            except KeyError:
                raise undefined(name) from None

        return read

    def index(self, e: ast.Index) -> Thunk:
        name = e.name.name
        args = [self.value(a) for a in e.args]
        sysvar = self.it.sysvars.getter(name, args)
        if sysvar is not None:
            return sysvar
        arrays = self.st.arrays

        def read() -> Value:
            arr = arrays.get(name)
            if arr is None:
                raise errors.RunError(
                    errors.VARIABLE_NOT_DEFINED, f"{name} is not an array (no DIM {name}(…))"
                )
            return arr.get(name, [f() for f in args])

        return read

    def element(self, e: ast.Element) -> Thunk:
        base = self.value(e.base)
        el = e.element.value
        return lambda: get_element(base(), el)

    def literal(self, e: ast.PositionLiteral, hint: VarType | None) -> Thunk:
        elems = [self.value(x) if x is not None else None for x in e.elements]
        flags = [self.value(x) if x is not None else None for x in (e.flags or ())]
        joint = hint is VarType.JOINT and e.flags is None

        def numbers() -> list[float]:
            out: list[float] = []
            for f in elems:
                v = f() if f is not None else 0.0
                if not isinstance(v, int | float):
                    raise type_error(f"a position constant holds numbers, not a {type_name(v)}")
                out.append(float(v))
            return out

        if joint:
            return lambda: Joints.from_degrees(numbers())

        def make_position() -> Value:
            vals = numbers()
            if len(vals) < 6:
                vals += [0.0] * (6 - len(vals))
            fl: list[int] = [7, 0]
            for i, f in enumerate(flags[:2]):
                if f is not None:
                    v = f()
                    if not isinstance(v, int | float):
                        raise type_error("structure flags are numbers")
                    fl[i] = round_half_away(v)
            return Position.from_degrees(vals, fl[0], fl[1])

        return make_position

    def unary(self, e: ast.Unary, hint: VarType | None) -> Thunk:
        inner = self.value(e.operand, hint)
        if e.op is ast.UnaryOp.PLUS:
            return inner
        if e.op is ast.UnaryOp.MINUS:

            def neg() -> Value:
                v = inner()
                if isinstance(v, int | float):
                    return -v
                if isinstance(v, Position):
                    return posmath.scale(v, -1.0)
                if isinstance(v, Joints):
                    return posmath.joints_scale(v, -1.0)
                raise type_error(f"cannot negate a {type_name(v)}")

            return neg

        def bit_not() -> Value:
            v = inner()
            if isinstance(v, int | float):
                return ~round_half_away(v)
            raise type_error(f"NOT needs a number, not a {type_name(v)}")

        return bit_not

    def binary(self, e: ast.Binary, hint: VarType | None) -> Thunk:
        if e.op.is_comparison:
            c = self.cond(e)
            t = TRUE_VALUE
            return lambda: t if c() else 0
        if e.op in (ast.BinaryOp.ADD, ast.BinaryOp.SUB):
            # The operands' own kind wins over the context's: in ``MOV J_CURR+(0,0,5,0,0,0)``
            # the move wants a position, but a constant added to joints is a joint constant.
            side = self._positional(e.left) or self._positional(e.right) or hint
        else:
            side = hint
            if side is None and e.op is not ast.BinaryOp.MUL:
                side = static_type(e.left)
        left = self.value(e.left, side)
        right = self.value(e.right, side if e.op in (ast.BinaryOp.ADD, ast.BinaryOp.SUB) else None)
        fn = ARITHMETIC[e.op]
        if e.op is ast.BinaryOp.ADD:

            def add() -> Value:
                a = left()
                b = right()
                if (type(a) is int and type(b) is int) or (type(a) is float and type(b) is float):
                    return a + b
                return op_add(a, b)

            return add
        return lambda: fn(left(), right())

    def _positional(self, e: ast.Expr) -> VarType | None:
        """POSITION or JOINT when `e` is known to be one (by DEF or by its name), else None."""
        declared = self.st.types.get(e.name) if isinstance(e, ast.Name) else None
        kind = declared or static_type(e)
        return kind if kind in (VarType.POSITION, VarType.JOINT) else None

    # -- conditions ------------------------------------------------------------------------
    def cond(self, e: ast.Expr) -> Cond:
        """A closure giving the truth of `e` (logical NOT/AND/OR/XOR)."""
        if isinstance(e, ast.Binary):
            if e.op.is_comparison:
                hint = static_type(e.left) or static_type(e.right)
                left = self.value(e.left, hint)
                right = self.value(e.right, hint)
                op = e.op
                if op is ast.BinaryOp.EQ:

                    def eq() -> bool:
                        a = left()
                        b = right()
                        if type(a) is type(b) and type(a) is not Position:
                            return a == b
                        return compare(op, a, b)

                    return eq
                return lambda: compare(op, left(), right())
            if e.op in LOGICAL:
                lc = self.cond(e.left)
                rc = self.cond(e.right)
                if e.op is ast.BinaryOp.AND:
                    return lambda: lc() and rc()
                if e.op is ast.BinaryOp.OR:
                    return lambda: lc() or rc()
                return lambda: lc() != rc()
        if isinstance(e, ast.Unary) and e.op is ast.UnaryOp.NOT:
            inner = self.cond(e.operand)
            return lambda: not inner()
        v = self.value(e)
        return lambda: truthy(v())

    # -- calls -----------------------------------------------------------------------------
    def call(self, e: ast.Call) -> Thunk:
        name = e.name
        if e.user or name.startswith("FN"):
            return self.user_call(e)
        args = [self.value(a) for a in e.args]
        spec = lang_model.FUNCTIONS.get(name)  # which functions exist, and their arities
        if spec is None or not spec.min_args <= len(args) <= spec.max_args:
            why = (
                f"takes {spec.arity_text} arguments, got {len(args)}"
                if spec is not None
                else "is not a MELFA BASIC IV function"
            )

            def wrong() -> Value:
                raise errors.RunError(errors.SYNTAX_ERROR, f"{name} {why}")

            return wrong
        special = robot_function(self.it.robot, name, args)
        if special is not None:
            return special
        if name == "RND":
            rnd = self.it.rnd
            return lambda: rnd([f() for f in args])
        fn = builtins.IMPLEMENTATIONS.get(name)
        if fn is None:

            def unsupported() -> Value:
                raise errors.RunError(
                    errors.NOT_SUPPORTED, f"{name} is not supported by the simulator"
                )

            return unsupported
        if len(args) == 1:
            a0 = args[0]
            return lambda: fn((a0(),))
        return lambda: fn([f() for f in args])

    def user_call(self, e: ast.Call) -> Thunk:
        st = self.st
        name = e.name
        args = [self.value(a) for a in e.args]

        def call() -> Value:
            fn = st.user_functions.get(name)
            if fn is None:
                raise errors.RunError(
                    errors.VARIABLE_NOT_DEFINED, f"function {name} is not defined (DEF {name})"
                )
            return fn([f() for f in args])

        return call

    def pallet(self, e: ast.Pallet) -> Thunk:
        number = self.value(e.pallet)
        index = self.value(e.index)
        st = self.st

        def grid() -> Value:
            n = number()
            k = index()
            if not isinstance(n, int | float) or not isinstance(k, int | float):
                raise type_error("PLT needs a pallet number and a grid number")
            return st.pallet_point(round_half_away(n), round_half_away(k))

        return grid
