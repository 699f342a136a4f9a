"""Declarations: DEF INTE/FLOAT/…/POS/JNT, DEF IO, DEF FN, DEF PLT, DEF ACT and ACT, DIM.

Types and user functions are program-wide (collected by `_declare` before any statement
is compiled, as the controller reads them at load); the rest take effect when their line
runs.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast
from melfa.lang import model as lang_model
from melfa.sim.interp import errors
from melfa.sim.interp.exprs import Thunk
from melfa.sim.interp.state import MAX_DIM_SIZE, ActDef, Array, PalletDef
from melfa.sim.interp.stmt_base import CompilerBase, Run, integer, nothing
from melfa.sim.interp.values import (
    Joints,
    Position,
    Value,
    VarType,
    default_value,
    implied_type,
)

_IO_WIDTH = {
    ast.IOType.BIT: 1,
    ast.IOType.BYTE: 8,
    ast.IOType.WORD: 16,
    ast.IOType.INTEGER: 16,
    ast.IOType.DWORD: 32,
}

_DECLARED = {
    ast.VarType.INTE: VarType.INTEGER,
    ast.VarType.FLOAT: VarType.FLOAT,
    ast.VarType.DOUBLE: VarType.DOUBLE,
    ast.VarType.CHAR: VarType.STRING,
    ast.VarType.POS: VarType.POSITION,
    ast.VarType.JNT: VarType.JOINT,
}


class DefinitionStatements(CompilerBase):
    """DEF statements, DIM and ACT."""

    def _declare(self, stmts: list[ast.Statement | None]) -> None:
        """DEF types and DEF FN are program-wide: collect them before compiling."""
        for s in stmts:
            if isinstance(s, ast.DefVar):
                for n in s.names:
                    self.st.types[n.name] = _DECLARED[s.type]
            elif isinstance(s, ast.DefIO):
                self.st.types[s.name.name] = VarType.IO
            elif isinstance(s, ast.DefFn):
                self.st.user_functions[s.name.name] = self._user_function(s)

    def _user_function(self, s: ast.DefFn) -> Callable[[list[Value]], Value]:
        params = [p.name for p in s.params]
        body = self.exprs.value(s.body)
        store = self.st.vars
        name = s.name.name
        depth = [0]

        def call(args: list[Value]) -> Value:
            if len(args) != len(params):
                raise errors.RunError(
                    errors.SYNTAX_ERROR, f"{name} takes {len(params)} argument(s), got {len(args)}"
                )
            if depth[0] >= 16:  # up to 16 nested user functions [S1 DEF FN]
                raise errors.RunError(errors.NESTING_OVER, f"{name} is nested too deep")
            saved = {p: store[p] for p in params if p in store}
            for p, a in zip(params, args, strict=True):
                store[p] = a
            depth[0] += 1
            try:
                return body()
            finally:
                depth[0] -= 1
                for p in params:
                    if p in saved:
                        store[p] = saved[p]
                    else:
                        store.pop(p, None)

        return call

    def _defvar(self, s: ast.DefVar, i: int) -> Run:
        st = self.st
        store = st.vars
        vtype = _DECLARED[s.type]
        names = [n.name for n in s.names]
        put = self.setter(s.names[0]) if s.value is not None else None
        value = self.exprs.value(s.value, vtype) if s.value is not None else None

        def run() -> None:
            for n in names:
                if n not in store:
                    d = default_value(vtype)
                    if d is not None:
                        store[n] = d
            if put is not None and value is not None:
                put(value())

        return run

    def _defio(self, s: ast.DefIO, i: int) -> Run:
        name = s.name.name
        width = _IO_WIDTH[s.io_type]
        bit = self.exprs.value(s.bit)
        mask = self.exprs.value(s.mask) if s.mask is not None else None
        defs = self.io_defs

        def run() -> None:
            defs[name] = (
                width,
                integer(bit(), "DEF IO"),
                integer(mask(), "DEF IO") if mask else None,
            )

        return run

    def _deffn(self, s: ast.DefFn, i: int) -> Run:
        return nothing  # registered program-wide by _declare

    def _defplt(self, s: ast.DefPlt, i: int) -> Run:
        it = self.it
        st = self.st
        num = self.exprs.value(s.number)
        pts = [self.exprs.value(e, VarType.POSITION) for e in (s.start, s.end_a, s.end_b)]
        diag = self.exprs.value(s.diagonal, VarType.POSITION) if s.diagonal is not None else None
        ca = self.exprs.value(s.count_a)
        cb = self.exprs.value(s.count_b)
        direction = self.exprs.value(s.direction)

        def pos(f: Thunk) -> Position:
            v = f()
            if isinstance(v, Joints):
                v = it.robot.to_position(v)
            if not isinstance(v, Position):
                raise errors.RunError(errors.TYPE_COMBINATION, "DEF PLT needs positions")
            return v

        def run() -> None:
            n = integer(num(), "DEF PLT")
            low, high, what = lang_model.RANGES["PLT"]  # the language's range (one home)
            if not low <= n <= high:
                raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"{what}, got {n}")
            d = integer(direction(), "DEF PLT")
            if d == 3:
                raise errors.RunError(
                    errors.NOT_SUPPORTED, "arc pallets (direction 3) are not simulated"
                )
            if d not in (1, 2):
                raise errors.RunError(
                    errors.ARGUMENT_OUT_OF_RANGE, f"pallet direction {d} is not 1..3"
                )
            na, nb = integer(ca(), "DEF PLT"), integer(cb(), "DEF PLT")
            if na < 1 or nb < 1:
                raise errors.RunError(
                    errors.ARGUMENT_OUT_OF_RANGE, "pallet counts must be 1 or more"
                )
            st.pallets[n] = PalletDef(
                pos(pts[0]), pos(pts[1]), pos(pts[2]), pos(diag) if diag else None, na, nb, d
            )

        return run

    def _defact(self, s: ast.DefAct, i: int) -> Run:
        st = self.st
        prio = self.exprs.value(s.priority)
        cond = self.exprs.cond(s.condition)
        dest = self.target(s.target)
        gosub = s.kind is ast.JumpKind.GOSUB
        mode = s.mode.upper() if s.mode else None

        def run() -> None:
            n = integer(prio(), "DEF ACT")
            low, high, what = lang_model.RANGES["ACT"]  # the language's range (one home)
            if not low <= n <= high:
                raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"{what}, got {n}")
            if isinstance(dest, errors.RunError):
                raise errors.RunError(errors.JUMP_DESTINATION_MISSING, dest.message)
            old = st.acts.get(n)
            st.acts[n] = ActDef(n, cond, gosub, dest, mode, old.enabled if old else False)

        return run

    def _actset(self, s: ast.ActSet, i: int) -> Run:
        st = self.st
        num = self.exprs.value(s.number)
        value = self.exprs.value(s.value)

        def run() -> None:
            n = integer(num(), "ACT")
            on = integer(value(), "ACT") != 0
            if n == 0:
                st.acts_master = on
                return
            act = st.acts.get(n)
            if act is None:
                raise errors.RunError(errors.VARIABLE_NOT_DEFINED, f"ACT {n} has no DEF ACT {n}")
            act.enabled = on

        return run

    def _dim(self, s: ast.Dim, i: int) -> Run:
        st = self.st
        specs = []
        for a in s.arrays:
            sizes = [self.exprs.value(e) for e in a.sizes]
            name = a.name.name
            specs.append((name, sizes, st.types.get(name) or implied_type(name)))

        def run() -> None:
            for name, sizes, vtype in specs:
                if name in st.arrays:
                    raise errors.RunError(errors.DUPLICATE_DEFINITION, f"{name} is already DIMmed")
                dims = tuple(integer(f(), "DIM") for f in sizes)
                if not 1 <= len(dims) <= 3 or any(not 1 <= d <= MAX_DIM_SIZE for d in dims):
                    raise errors.RunError(
                        errors.ARRAY_ELEMENT, f"DIM {name}: 1 to 3 sizes of 1..{MAX_DIM_SIZE}"
                    )
                st.arrays[name] = Array(dims, vtype)

        return run
