"""Assignment targets (variables, elements, arrays, system variables, DEF IO signals),
the assignment statement (with its pulse form ``M_OUT(n)=1 DLY t``) and PRINT.

One place decides how a value is stored, so ``=``, FOR counters, DEF with a value and
NEXT all coerce the same way.
"""

from __future__ import annotations

from melfa.lang import ast
from melfa.sim.interp import errors
from melfa.sim.interp.builtins import format_number
from melfa.sim.interp.exprs import Thunk
from melfa.sim.interp.state import WaitCond
from melfa.sim.interp.stmt_base import CompilerBase, Run, Setter, integer, number, refuse_set
from melfa.sim.interp.values import Value, VarType, coerce, implied_type, set_element

DEF_IO_READS_INPUTS = True
"""[GUESS] Reading a DEF IO variable reads input signals; assigning one writes outputs."""


class VariableStatements(CompilerBase):
    """Assignments and the setters other statements reuse."""

    def setter(self, target: ast.AssignTarget, hint_value: ast.Expr | None = None) -> Setter:
        it = self.it
        st = self.st
        if isinstance(target, ast.Element):
            base = target.base
            if not isinstance(base, ast.Name | ast.Index):
                return refuse_set("only a variable's element can be assigned")
            read = self.exprs.value(base)
            write = self.setter(base)
            el = target.element.value

            def set_el(v: Value) -> None:
                write(set_element(read(), el, v))

            return set_el
        if isinstance(target, ast.Index):
            name = target.name.name
            args = [self.exprs.value(a) for a in target.args]
            sys_set = it.sysvars.setter(name, args)
            if sys_set is not None:
                return sys_set
            arrays = st.arrays

            def set_item(v: Value) -> None:
                arr = arrays.get(name)
                if arr is None:
                    raise errors.RunError(
                        errors.VARIABLE_NOT_DEFINED, f"{name} is not an array (no DIM {name}(…))"
                    )
                key = arr.key(name, [f() for f in args])
                arr.data[key] = coerce(v, arr.vtype, f"{name}(…)")

            return set_item
        name = target.name
        sys_set = it.sysvars.setter(name, ())
        if sys_set is not None:
            return sys_set
        vtype = st.types.get(name) or implied_type(name)
        store = st.vars
        if vtype is VarType.IO:
            return self._io_setter(name)
        if vtype is VarType.NUMBER:

            def set_num(v: Value) -> None:
                if type(v) is int or type(v) is float:
                    store[name] = v
                else:
                    store[name] = coerce(v, VarType.NUMBER, name)

            return set_num

        def set_typed(v: Value) -> None:
            store[name] = coerce(v, vtype, name)

        return set_typed

    def _io_setter(self, name: str) -> Setter:
        io = self.it.io
        defs = self.io_defs

        def set_io(v: Value) -> None:
            d = defs.get(name)
            if d is None:
                raise errors.RunError(
                    errors.VARIABLE_NOT_DEFINED, f"DEF IO {name} not executed yet"
                )
            width, bit, mask = d
            value = integer(v, name)
            if mask is not None:
                value = (io.read_outputs(bit, width) & ~mask) | (value & mask)
            io.write_outputs(bit, width, value)

        return set_io

    def io_reader(self, name: str) -> Thunk:
        io = self.it.io
        defs = self.io_defs

        def read() -> Value:
            d = defs.get(name)
            if d is None:
                raise errors.RunError(
                    errors.VARIABLE_NOT_DEFINED, f"DEF IO {name} not executed yet"
                )
            width, bit, mask = d
            v = io.read_inputs(bit, width) if DEF_IO_READS_INPUTS else io.read_outputs(bit, width)
            return v & mask if mask is not None else v

        return read

    def _assign(self, s: ast.Assign, i: int) -> Run:
        tgt = s.target
        hint = None
        if isinstance(tgt, ast.Name):
            hint = self.st.types.get(tgt.name) or implied_type(tgt.name)
        value = self.exprs.value(s.value, hint)
        put = self.setter(tgt)
        if s.pulse is None:
            return lambda: put(value())
        read_old = self.exprs.value(tgt) if not isinstance(tgt, ast.Element) else None
        pulse = self.exprs.value(s.pulse)
        st = self.st

        def pulsed() -> None:
            try:
                old: Value = read_old() if read_old is not None else 0
            except errors.RunError:
                old = 0
            put(value())
            seconds = number(pulse(), "DLY")
            st.pulses.append((st.now + seconds, lambda: put(old)))

        return pulsed

    def _input(self, s: ast.Input, i: int) -> Run:
        """``INPUT #n, a, b$``: the next line fed to file n (`Interpreter.feed_line`), its
        comma-separated items into the variables; with none there the program waits in
        INPUT, as for a line from the port [S1 INPUT]."""
        st = self.st
        feed = self.it.feed
        channel = self.exprs.value(s.channel) if s.channel is not None else None
        targets = [(self.setter(t), _kind(self, t)) for t in s.targets]

        def run() -> None:
            n = integer(channel(), "INPUT #") if channel is not None else 1
            queue = feed.get(n)
            if not queue:
                st.pc = i  # read again when a line is there
                st.block = WaitCond(lambda: bool(feed.get(n)))
                return
            items = queue.popleft().split(",")
            if len(items) < len(targets):
                raise errors.RunError(
                    errors.TYPE_COMBINATION,
                    f"INPUT #{n} read {len(items)} item(s) for {len(targets)} variable(s)",
                )
            for (put, vtype), item in zip(targets, items, strict=False):
                put(_read_item(item.strip(), vtype, n))

        return run

    def _print(self, s: ast.Print, i: int) -> Run:
        st = self.st
        items = [self.exprs.value(e) for e in s.items]

        def run() -> None:
            parts = []
            for f in items:
                v = f()
                parts.append(format_number(v) if isinstance(v, int | float) else str(v))
            st.console.append(",".join(parts))

        return run


def _kind(compiler: VariableStatements, target: ast.AssignTarget) -> VarType:
    if isinstance(target, ast.Name):
        return compiler.st.types.get(target.name) or implied_type(target.name)
    return VarType.NUMBER


def _read_item(item: str, vtype: VarType, channel: int) -> Value:
    """One item of an INPUT line as the variable's type (a number or a string)."""
    if vtype is VarType.STRING:
        return item.strip('"')
    try:
        number = float(item)
    except ValueError:
        raise errors.RunError(
            errors.TYPE_COMBINATION, f"INPUT #{channel}: {item!r} is not a number"
        ) from None
    return int(number) if number.is_integer() and "." not in item else number
