"""Control flow: jumps, subroutines, IF, loops, SELECT, BREAK and WAIT.

Jumps and block ends are resolved at compile time to step indices (`Structure`), so a
running program only assigns `st.pc`. Loops keep their state on the interpreter's loop
stack, which GOSUB/RETURN trim, as the controller does.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast
from melfa.sim.interp import errors
from melfa.sim.interp.exprs import compare
from melfa.sim.interp.state import Loop, WaitCond
from melfa.sim.interp.stmt_base import CompilerBase, Run, fail, integer, nothing, number, raiser
from melfa.sim.interp.values import Value


class FlowStatements(CompilerBase):
    """GOTO/GOSUB/ON/RETURN, IF forms, FOR/NEXT, WHILE/WEND, SELECT/CASE, BREAK, WAIT."""

    def target(self, t: ast.LineRef | ast.LabelRef) -> int | errors.RunError:
        if isinstance(t, ast.LineRef):
            i = self.numbers.get(t.number)
            if i is None:
                return errors.RunError(errors.LINE_NOT_FOUND, f"line {t.number} does not exist")
            return i
        i = self.labels.get(t.name)
        if i is None:
            return errors.RunError(
                errors.JUMP_DESTINATION_MISSING, f"label *{t.name} does not exist"
            )
        return i

    def goto(self, t: ast.LineRef | ast.LabelRef) -> Run:
        dest = self.target(t)
        if isinstance(dest, errors.RunError):
            return raiser(dest)
        st = self.st

        def run() -> None:
            st.pc = dest

        return run

    def _goto(self, s: ast.Goto, i: int) -> Run:
        return self.goto(s.target)

    def _gosub(self, s: ast.Gosub, i: int) -> Run:
        dest = self.target(s.target)
        if isinstance(dest, errors.RunError):
            return raiser(dest)
        st = self.st
        return lambda: st.gosub(dest)

    def _on_jump(self, s: ast.OnJump, i: int) -> Run:
        st = self.st
        sel = self.exprs.value(s.selector)
        dests = [self.target(t) for t in s.targets]
        gosub = s.kind is ast.JumpKind.GOSUB

        def run() -> None:
            n = integer(sel(), "ON")
            if n < 0 or n > 32767:  # [S1 ON GOTO]
                raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"ON value {n} is out of range")
            if not 1 <= n <= len(dests):
                return  # 0 or more than the list: fall through
            d = dests[n - 1]
            if isinstance(d, errors.RunError):
                raise d
            if gosub:
                st.gosub(d)
            else:
                st.pc = d

        return run

    def _return(self, s: ast.Return, i: int) -> Run:
        st = self.st
        mode = self.exprs.value(s.mode) if s.mode is not None else None

        def run() -> None:
            st.return_(integer(mode(), "RETURN") if mode is not None else None)

        return run

    def _if(self, s: ast.If, i: int) -> Run:
        st = self.st
        cond = self.exprs.cond(s.condition)
        if s.is_block:
            els = self.structure.if_else.get(i)
            end = self.structure.if_end.get(i)
            if end is None:
                return fail(errors.IF_ENDIF_UNMATCH, "IF without ENDIF")
            skip_to = (els if els is not None else end) + 1

            def block_if() -> None:
                if not cond():
                    st.pc = skip_to

            return block_if
        then = self._branch(s.then, i)
        other = self._branch(s.else_, i) if s.else_ is not None else None

        def line_if() -> None:
            if cond():
                then()
            elif other is not None:
                other()

        return line_if

    def _branch(self, b: ast.LineRef | ast.LabelRef | ast.Statement | None, i: int) -> Run:
        if b is None:
            return nothing
        if isinstance(b, ast.LineRef | ast.LabelRef):
            return self.goto(b)
        return self.statement(b, i)

    def _else(self, s: ast.Else, i: int) -> Run:
        # reached at the end of the THEN part: go past ENDIF
        end = self.structure.else_end.get(i)
        if end is None:
            return fail(errors.IF_ELSE_UNMATCH, "ELSE without a block IF")
        st = self.st
        dest = end + 1

        def run() -> None:
            st.pc = dest

        return run

    def _for(self, s: ast.For, i: int) -> Run:
        st = self.st
        match = self.structure.for_next.get(i)
        if match is None:
            return fail(errors.FOR_NEXT_UNMATCH, "FOR without NEXT")
        next_index, k = match
        counter = s.counter.name
        put = self.setter(s.counter)
        start = self.exprs.value(s.start)
        end = self.exprs.value(s.end)
        step = self.exprs.value(s.step) if s.step is not None else (lambda: 1)
        loops = st.loops

        def run() -> None:
            a = start()
            b = number(end(), "FOR … TO")
            d = number(step(), "FOR … STEP")
            number(a, "FOR")
            put(a)
            for j in range(len(loops) - 1, -1, -1):  # re-entered: forget the old loop
                if loops[j].start == i:
                    del loops[j:]
                    break
            av = float(a)  # type: ignore[arg-type]
            if (d >= 0 and av > b) or (d < 0 and av < b):
                st.pc = next_index + 1  # zero-trip: on after the NEXT (and its other loops)
                handler = st.next_handlers.get(next_index)
                if handler is not None:
                    handler(k + 1)
                return
            if len(loops) >= errors.MAX_LOOP_DEPTH:
                raise errors.RunError(errors.NESTING_OVER, "FOR/WHILE nested deeper than 16")
            loops.append(Loop(i, counter, b, d))

        return run

    def _next(self, s: ast.Next, i: int) -> Run:
        st = self.st
        names: list[str | None] = [c.name for c in s.counters] or [None]
        setters = {c.name: self.setter(c) for c in s.counters}
        store = st.vars
        loops = st.loops

        def run_from(k: int) -> None:
            for name in names[k:]:
                if not loops or loops[-1].counter is None:
                    raise errors.RunError(errors.FOR_NEXT_UNMATCH, "NEXT without FOR")
                loop = loops[-1]
                if name is not None and loop.counter != name:
                    raise errors.RunError(
                        errors.FOR_NEXT_UNMATCH, f"NEXT {name} does not close FOR {loop.counter}"
                    )
                cname = loop.counter
                assert cname is not None
                v = store.get(cname)
                if not isinstance(v, int | float):
                    raise errors.RunError(errors.UNDEFINED_VARIABLE, f"FOR counter {cname} lost")
                v = v + loop.step
                if type(v) is float and v == int(v) and type(store[cname]) is int:
                    v = int(v)
                put = setters.get(cname)
                if put is not None:
                    put(v)
                else:
                    store[cname] = v
                if (loop.step >= 0 and v <= loop.end) or (loop.step < 0 and v >= loop.end):
                    st.pc = loop.start + 1
                    return
                loops.pop()

        st.next_handlers[i] = run_from
        return lambda: run_from(0)

    def _while(self, s: ast.While, i: int) -> Run:
        st = self.st
        cond = self.exprs.cond(s.condition)
        wend = self.structure.while_wend.get(i)
        if wend is None:
            return fail(errors.WHILE_WEND_UNMATCH, "WHILE without WEND")
        loops = st.loops
        after = wend + 1

        def run() -> None:
            top = loops[-1] if loops else None
            looping = top is not None and top.start == i and top.counter is None
            if cond():
                if not looping:
                    if len(loops) >= errors.MAX_LOOP_DEPTH:
                        raise errors.RunError(
                            errors.NESTING_OVER, "FOR/WHILE nested deeper than 16"
                        )
                    loops.append(Loop(i))
            else:
                if looping:
                    loops.pop()
                st.pc = after

        return run

    def _wend(self, s: ast.Wend, i: int) -> Run:
        st = self.st
        start = self.structure.wend_while.get(i)
        if start is None:
            return fail(errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
        loops = st.loops

        def run() -> None:
            if not loops or loops[-1].start != start:
                raise errors.RunError(errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
            st.pc = start

        return run

    def _select(self, s: ast.Select, i: int) -> Run:
        st = self.st
        subject = self.exprs.value(s.subject)
        end = self.structure.select_end.get(i)
        if end is None:
            return fail(errors.SELECT_UNMATCH, "SELECT without END SELECT")
        tests: list[tuple[Callable[[Value], bool] | None, int]] = []
        for c in self.structure.select_cases.get(i, []):
            stmt = self.it_stmt(c)
            if isinstance(stmt, ast.Case):
                tests.append((self._case_test(stmt), c + 1))
            else:
                tests.append((None, c + 1))  # DEFAULT
        after = end + 1

        def run() -> None:
            v = subject()
            default = None
            for test, dest in tests:
                if test is None:
                    if default is None:
                        default = dest
                elif test(v):
                    st.pc = dest
                    return
            st.pc = default if default is not None else after

        return run

    def it_stmt(self, index: int) -> ast.Statement | None:
        return self._stmts[index]

    def _case_test(self, c: ast.Case) -> Callable[[Value], bool]:
        lo = self.exprs.value(c.value)
        if c.kind is ast.CaseKind.RANGE and c.high is not None:
            hi = self.exprs.value(c.high)
            return lambda v: compare(ast.BinaryOp.GE, v, lo()) and compare(ast.BinaryOp.LE, v, hi())
        op = c.op if c.kind is ast.CaseKind.IS and c.op is not None else ast.BinaryOp.EQ
        return lambda v: compare(op, v, lo())

    def _break(self, s: ast.Break, i: int) -> Run:
        st = self.st
        inner = self.structure.breaks.get(i)
        if inner is None:
            return fail(errors.SELECT_UNMATCH, "BREAK outside SELECT/FOR/WHILE")
        kind, opener = inner
        if kind == "SELECT":
            end = self.structure.select_end.get(opener)
        elif kind == "WHILE":
            end = self.structure.while_wend.get(opener)
        else:
            m = self.structure.for_next.get(opener)
            end = m[0] if m else None
        if end is None:
            return fail(errors.SELECT_UNMATCH, "BREAK in an unclosed block")
        dest = end + 1
        loops = st.loops

        def run() -> None:
            if kind != "SELECT":
                for j in range(len(loops) - 1, -1, -1):
                    if loops[j].start == opener:
                        del loops[j:]
                        break
            st.pc = dest

        return run

    def _wait(self, s: ast.Wait, i: int) -> Run:
        st = self.st
        cond = self.exprs.cond(s.condition)

        def run() -> None:
            if not cond():
                st.block = WaitCond(cond)

        return run
