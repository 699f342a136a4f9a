"""Statements compiled to closures, with jumps and blocks resolved to step indices.

`Compiler.compile_program` orders the steps (ascending step numbers, as the controller
executes them [S2 §4.3.4]), matches FOR/NEXT, WHILE/WEND, IF/ELSE/ENDIF and
SELECT/CASE/END SELECT once, and turns every statement into a closure over the
interpreter's state. A structure error (a NEXT without FOR, a jump to a missing line) is
not a load failure: like the controller, the program stops with its error number when it
reaches that line.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from melfa.lang import ast
from melfa.sim.interp import errors, posmath
from melfa.sim.interp.exprs import ExprCompiler, Thunk
from melfa.sim.interp.robot import ArcKind
from melfa.sim.interp.values import (
    Joints,
    Position,
    Value,
    VarType,
    coerce,
    default_value,
    implied_type,
    round_half_away,
    set_element,
    type_name,
)

if TYPE_CHECKING:
    from melfa.sim.interp.interpreter import Interpreter, Step

Run = Callable[[], None]
Setter = Callable[[Value], None]

DEF_IO_READS_INPUTS = True
"""[GUESS] Reading a DEF IO variable reads input signals; assigning one writes outputs."""

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

#: Statements accepted and ignored: they tune a real servo/mechanism the simulator lacks.
IGNORED_COMMANDS = frozenset(
    {
        ast.CommandKind.CNT,
        ast.CommandKind.FINE,
        ast.CommandKind.LOADSET,
        ast.CommandKind.TORQ,
        ast.CommandKind.JRC,
        ast.CommandKind.CMPG,
        ast.CommandKind.PRIORITY,
        ast.CommandKind.GETM,
        ast.CommandKind.RELM,
        ast.CommandKind.SKIP,
    }
)

#: Statements the simulator refuses (one program, no files, no other tasks).
REFUSED_COMMANDS = frozenset(
    {
        ast.CommandKind.CALLP,
        ast.CommandKind.XLOAD,
        ast.CommandKind.XRUN,
        ast.CommandKind.XSTP,
        ast.CommandKind.XRST,
        ast.CommandKind.XCLR,
        ast.CommandKind.CHRSRCH,
        ast.CommandKind.DEF_ARCH,
    }
)


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


@dataclass(slots=True)
class Structure:
    """Block matching results, by step index."""

    for_next: dict[int, tuple[int, int]] = field(default_factory=dict)  # for -> (next, k)
    while_wend: dict[int, int] = field(default_factory=dict)
    wend_while: dict[int, int] = field(default_factory=dict)
    if_else: dict[int, int | None] = field(default_factory=dict)
    if_end: dict[int, int] = field(default_factory=dict)
    else_end: dict[int, int] = field(default_factory=dict)
    select_cases: dict[int, list[int]] = field(default_factory=dict)
    select_end: dict[int, int] = field(default_factory=dict)
    breaks: dict[int, tuple[str, int]] = field(default_factory=dict)  # -> (kind, opener)
    problems: dict[int, tuple[int, str]] = field(default_factory=dict)


class Compiler:
    """Compiles a parsed program for one interpreter."""

    def __init__(self, it: Interpreter) -> None:
        self.it = it
        self.exprs = ExprCompiler(it)
        self.numbers: dict[int, int] = {}
        self.labels: dict[str, int] = {}
        self.structure = Structure()
        self.io_defs: dict[str, tuple[int, int, int | None]] = {}
        self._stmts: list[ast.Statement | None] = []

    # ------------------------------------------------------------------ program
    def compile_program(self, program: ast.Program, points: dict[str, Value]) -> list[Step]:
        from melfa.sim.interp.interpreter import Step

        lines = [ln for ln in program.lines if ln.number is not None or ln.label is not None
                 or ln.statement is not None]  # fmt: skip
        numbered = any(ln.number is not None for ln in lines)
        executable: list[ast.Line] = []
        for ln in lines:
            if numbered and ln.number is None:
                if ln.statement is not None and self._is_point(ln.statement):
                    self.it._take_point(ln.statement, points, ln.span.line)
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
            executable.sort(key=lambda ln: ln.number or 0)
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
        self.structure = self._match(stmts)
        steps = []
        for i, ln in enumerate(executable):
            problem = self.structure.problems.get(i)
            if problem is not None:
                run = fail(*problem)
            elif ln.statement is None:
                run = _nothing
            else:
                run = self.statement(ln.statement, i)
            steps.append(Step(self._shown(ln), run, ln.span.line))
        return steps

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
        return self.statement(stmt, self.it.current)

    # ------------------------------------------------------------------ declarations
    def _declare(self, stmts: list[ast.Statement | None]) -> None:
        """DEF types and DEF FN are program-wide: collect them before compiling."""
        for s in stmts:
            if isinstance(s, ast.DefVar):
                for n in s.names:
                    self.it.types[n.name] = _DECLARED[s.type]
            elif isinstance(s, ast.DefIO):
                self.it.types[s.name.name] = VarType.IO
            elif isinstance(s, ast.DefFn):
                self.it.user_functions[s.name.name] = self._user_function(s)

    def _user_function(self, s: ast.DefFn) -> Callable[[list[Value]], Value]:
        params = [p.name for p in s.params]
        body = self.exprs.value(s.body)
        store = self.it.vars
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

    # ------------------------------------------------------------------ blocks
    def _match(self, stmts: list[ast.Statement | None]) -> Structure:
        st = Structure()
        stack: list[tuple[str, int]] = []
        for i, s in enumerate(stmts):
            if isinstance(s, ast.For):
                stack.append(("FOR", i))
            elif isinstance(s, ast.While):
                stack.append(("WHILE", i))
            elif isinstance(s, ast.If) and s.is_block:
                stack.append(("IF", i))
                st.if_else[i] = None
            elif isinstance(s, ast.Select):
                stack.append(("SELECT", i))
                st.select_cases[i] = []
            elif isinstance(s, ast.Next):
                for k in range(max(1, len(s.counters))):
                    if not stack or stack[-1][0] != "FOR":
                        st.problems[i] = (errors.FOR_NEXT_UNMATCH, "NEXT without FOR")
                        break
                    st.for_next[stack.pop()[1]] = (i, k)
            elif isinstance(s, ast.Wend):
                if not stack or stack[-1][0] != "WHILE":
                    st.problems[i] = (errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
                    continue
                w = stack.pop()[1]
                st.while_wend[w] = i
                st.wend_while[i] = w
            elif isinstance(s, ast.Else):
                if not stack or stack[-1][0] != "IF" or st.if_else[stack[-1][1]] is not None:
                    st.problems[i] = (errors.IF_ELSE_UNMATCH, "ELSE without a block IF")
                    continue
                st.if_else[stack[-1][1]] = i
            elif isinstance(s, ast.EndIf):
                if not stack or stack[-1][0] != "IF":
                    st.problems[i] = (errors.IF_ENDIF_UNMATCH, "ENDIF without a block IF")
                    continue
                opener = stack.pop()[1]
                st.if_end[opener] = i
                els = st.if_else[opener]
                if els is not None:
                    st.else_end[els] = i
            elif isinstance(s, ast.Case | ast.Default):
                sel = next((j for kind, j in reversed(stack) if kind == "SELECT"), None)
                if sel is None:
                    st.problems[i] = (errors.SELECT_UNMATCH, "CASE outside SELECT")
                    continue
                st.select_cases[sel].append(i)
            elif isinstance(s, ast.EndSelect):
                if not stack or stack[-1][0] != "SELECT":
                    st.problems[i] = (errors.SELECT_UNMATCH, "END SELECT without SELECT")
                    continue
                st.select_end[stack.pop()[1]] = i
            elif isinstance(s, ast.Break) or (
                isinstance(s, ast.If)
                and (isinstance(s.then, ast.Break) or isinstance(s.else_, ast.Break))
            ):
                inner = next(
                    (
                        (kind, j)
                        for kind, j in reversed(stack)
                        if kind in ("FOR", "WHILE", "SELECT")
                    ),
                    None,
                )
                if inner is None:
                    st.problems[i] = (errors.SELECT_UNMATCH, "BREAK outside SELECT/FOR/WHILE")
                else:
                    st.breaks[i] = inner
        unclosed = {
            "FOR": (errors.FOR_NEXT_UNMATCH, "FOR without NEXT"),
            "WHILE": (errors.WHILE_WEND_UNMATCH, "WHILE without WEND"),
            "IF": (errors.IF_ENDIF_UNMATCH, "IF without ENDIF"),
            "SELECT": (errors.SELECT_UNMATCH, "SELECT without END SELECT"),
        }
        for kind, j in stack:
            st.problems[j] = unclosed[kind]
        return st

    # ------------------------------------------------------------------ jumps
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
            return _raiser(dest)
        it = self.it

        def run() -> None:
            it.pc = dest

        return run

    # ------------------------------------------------------------------ assignment
    def setter(self, target: ast.AssignTarget, hint_value: ast.Expr | None = None) -> Setter:
        it = self.it
        if isinstance(target, ast.Element):
            base = target.base
            if not isinstance(base, ast.Name | ast.Index):
                return _refuse_set("only a variable's element can be assigned")
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
            arrays = it.arrays

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
        vtype = it.types.get(name) or implied_type(name)
        store = it.vars
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

    # ------------------------------------------------------------------ statements
    def statement(self, s: ast.Statement, i: int) -> Run:
        method = _DISPATCH.get(type(s))
        if method is None:
            return fail(
                errors.NOT_SUPPORTED, f"{type(s).__name__} is not supported by the simulator"
            )
        return method(self, s, i)

    def _assign(self, s: ast.Assign, i: int) -> Run:
        tgt = s.target
        hint = None
        if isinstance(tgt, ast.Name):
            hint = self.it.types.get(tgt.name) or implied_type(tgt.name)
        value = self.exprs.value(s.value, hint)
        put = self.setter(tgt)
        if s.pulse is None:
            return lambda: put(value())
        read_old = self.exprs.value(tgt) if not isinstance(tgt, ast.Element) else None
        pulse = self.exprs.value(s.pulse)
        it = self.it

        def pulsed() -> None:
            try:
                old: Value = read_old() if read_old is not None else 0
            except errors.RunError:
                old = 0
            put(value())
            seconds = number(pulse(), "DLY")
            it.pulses.append((it.now + seconds, lambda: put(old)))

        return pulsed

    def _move(self, s: ast.Move, i: int) -> Run:
        it = self.it
        robot = it.robot
        target = self.exprs.value(s.target, VarType.POSITION) if s.target is not None else None
        close = self.exprs.value(s.close) if s.close is not None else None
        linear = s.kind is ast.MoveKind.MVS
        appended = self._appended(s.appended, i)

        def goal() -> Position | Joints:
            if target is None:
                base: Value = robot.position()
            else:
                base = target()
            if close is None:
                if not isinstance(base, Position | Joints):
                    raise errors.RunError(
                        errors.TYPE_COMBINATION, f"cannot move to a {type_name(base)}"
                    )
                return base
            d = number(close(), "the close distance")
            if isinstance(base, Joints):
                base = robot.to_position(base)
            if not isinstance(base, Position):
                raise errors.RunError(
                    errors.TYPE_COMBINATION, f"cannot move to a {type_name(base)}"
                )
            return posmath.tool_offset(base, d)

        def run() -> None:
            g = goal()
            if linear:
                p = g if isinstance(g, Position) else robot.to_position(g)
                it.start_motion(lambda now: robot.move_linear(p, now), watch=appended[1])
            else:
                it.start_motion(lambda now: robot.move_joint(g, now), watch=appended[1])
            if appended[0] is not None:
                appended[0]()

        return run

    def _appended(
        self, a: ast.Appended | None, i: int
    ) -> tuple[Run | None, tuple[Callable[[], bool], Run] | None]:
        """(action run at the start of the move, (condition, action) watched during it)."""
        if a is None:
            return None, None
        it = self.it
        act = a.action
        if isinstance(act, ast.Command) and act.kind is ast.CommandKind.SKIP:
            action: Run = it.skip_motion
        elif isinstance(act, ast.Command) and act.kind is ast.CommandKind.HLT:

            def action() -> None:
                it._halt(it.now)

        else:
            action = self.statement(act, i)
        if a.condition is None:
            return action, None
        return None, (self.exprs.cond(a.condition), action)

    def _arc(self, s: ast.ArcMove, i: int) -> Run:
        it = self.it
        robot = it.robot
        pts = [self.exprs.value(p, VarType.POSITION) for p in s.points]
        kind = ArcKind(s.kind.value)
        appended = self._appended(s.appended, i)
        if len(pts) != 3:
            return fail(errors.SYNTAX_ERROR, f"{kind.value} needs 3 positions")

        def run() -> None:
            ps: list[Position] = []
            for f in pts:
                p = f()
                if isinstance(p, Joints):
                    p = robot.to_position(p)
                if not isinstance(p, Position):
                    raise errors.RunError(errors.TYPE_COMBINATION, f"{kind.value} needs positions")
                ps.append(p)
            points = tuple(ps)
            it.start_motion(lambda now: robot.move_arc(kind, points, now), watch=appended[1])
            if appended[0] is not None:
                appended[0]()

        return run

    def _arch(self, s: ast.ArchMove, i: int) -> Run:
        it = self.it
        robot = it.robot
        target = self.exprs.value(s.target, VarType.POSITION)
        appended = self._appended(s.appended, i)

        def run() -> None:
            g = target()
            if isinstance(g, Joints):
                g = robot.to_position(g)
            if not isinstance(g, Position):
                raise errors.RunError(errors.TYPE_COMBINATION, "MVA needs a position")
            goal = g
            it.start_motion(lambda now: robot.move_arch(goal, now), watch=appended[1])
            if appended[0] is not None:
                appended[0]()

        return run

    def _command(self, s: ast.Command, i: int) -> Run:
        it = self.it
        robot = it.robot
        k = s.kind
        args = [self.exprs.value(a) if a is not None else None for a in s.args]
        if k in IGNORED_COMMANDS:
            return _nothing
        if k in REFUSED_COMMANDS:
            return fail(
                errors.NOT_SUPPORTED,
                f"{k.value} is not supported by the simulator (it runs one program)",
            )

        def arg(n: int, what: str) -> float:
            f = args[n] if n < len(args) else None
            if f is None:
                raise errors.RunError(errors.SYNTAX_ERROR, f"{k.value} needs {what}")
            return number(f(), f"{k.value}")

        if k in (ast.CommandKind.OVRD, ast.CommandKind.JOVRD, ast.CommandKind.SPD):
            what = k.value
            first = args[0] if args else None
            if first is None:
                return fail(errors.SYNTAX_ERROR, f"{what} needs a value")
            return lambda: it.set_speed(what, first())
        if k is ast.CommandKind.ACCEL:

            def accel() -> None:
                acc = arg(0, "a value") if args and args[0] is not None else 100.0
                dec = arg(1, "a value") if len(args) > 1 and args[1] is not None else acc
                if acc <= 0 or dec <= 0:
                    raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, "ACCEL must be > 0 %")
                robot.set_speeds(accel=(acc, dec))

            return accel
        if k in (ast.CommandKind.HOPEN, ast.CommandKind.HCLOSE):
            opening = k is ast.CommandKind.HOPEN

            def hand() -> None:
                n = integer(arg(0, "a hand number"), "hand")
                if not 1 <= n <= 8:
                    raise errors.RunError(
                        errors.ARGUMENT_OUT_OF_RANGE, f"hand number must be 1..8, got {n}"
                    )
                robot.set_hand(n, opening, it.now)

            return hand
        if k in (ast.CommandKind.TOOL, ast.CommandKind.BASE):
            is_tool = k is ast.CommandKind.TOOL
            src = args[0] if args else None
            if src is None:
                return fail(errors.SYNTAX_ERROR, f"{k.value} needs a position")

            def frame() -> None:
                v = src()
                if isinstance(v, int | float) and v == 0:
                    v = Position(fl1=0)  # TOOL 0 / BASE 0: no conversion (P_NTOOL/P_NBASE)
                if not isinstance(v, Position):
                    raise errors.RunError(
                        errors.NOT_SUPPORTED
                        if isinstance(v, int | float)
                        else errors.TYPE_COMBINATION,
                        f"{k.value} needs a position (numbered frames are not simulated)",
                    )
                if is_tool:
                    robot.set_tool(v)
                else:
                    robot.set_base(v)

            return frame
        if k is ast.CommandKind.END:
            return it.end
        if k is ast.CommandKind.HLT:
            return it.hold
        if k is ast.CommandKind.DLY:

            def delay() -> None:
                from melfa.sim.interp.interpreter import Delay

                t = arg(0, "a time in seconds")
                if t < 0:
                    raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, "DLY time is negative")
                it.block = Delay(it.now + t)

            return delay
        if k is ast.CommandKind.ERROR:

            def user_error() -> None:
                n = integer(arg(0, "an error number"), "ERROR")
                if not 9000 <= n <= 9299:  # [S1 ERROR]
                    raise errors.RunError(
                        errors.ARGUMENT_OUT_OF_RANGE, f"ERROR number must be 9000..9299, got {n}"
                    )
                raise errors.RunError(n, f"user error {n}")

            return user_error
        if k is ast.CommandKind.RESET_ERR:

            def reset_err() -> None:
                it.caution = None

            return reset_err
        if k is ast.CommandKind.CLR:
            return _nothing
        return fail(errors.NOT_SUPPORTED, f"{k.value} is not supported by the simulator")

    def _switch(self, s: ast.Switch, i: int) -> Run:
        if s.kind is not ast.SwitchKind.SERVO:
            return _nothing
        it = self.it
        on = s.on
        return lambda: it.robot.set_servo(on, it.now)

    def _goto(self, s: ast.Goto, i: int) -> Run:
        return self.goto(s.target)

    def _gosub(self, s: ast.Gosub, i: int) -> Run:
        dest = self.target(s.target)
        if isinstance(dest, errors.RunError):
            return _raiser(dest)
        it = self.it
        return lambda: it.gosub(dest)

    def _on_jump(self, s: ast.OnJump, i: int) -> Run:
        it = self.it
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
                it.gosub(d)
            else:
                it.pc = d

        return run

    def _return(self, s: ast.Return, i: int) -> Run:
        it = self.it
        mode = self.exprs.value(s.mode) if s.mode is not None else None

        def run() -> None:
            it.return_(integer(mode(), "RETURN") if mode is not None else None)

        return run

    def _if(self, s: ast.If, i: int) -> Run:
        it = self.it
        cond = self.exprs.cond(s.condition)
        if s.is_block:
            els = self.structure.if_else.get(i)
            end = self.structure.if_end.get(i)
            if end is None:
                return fail(errors.IF_ENDIF_UNMATCH, "IF without ENDIF")
            skip_to = (els if els is not None else end) + 1

            def block_if() -> None:
                if not cond():
                    it.pc = skip_to

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
            return _nothing
        if isinstance(b, ast.LineRef | ast.LabelRef):
            return self.goto(b)
        return self.statement(b, i)

    def _else(self, s: ast.Else, i: int) -> Run:
        # reached at the end of the THEN part: go past ENDIF
        end = self.structure.else_end.get(i)
        if end is None:
            return fail(errors.IF_ELSE_UNMATCH, "ELSE without a block IF")
        it = self.it
        dest = end + 1

        def run() -> None:
            it.pc = dest

        return run

    def _for(self, s: ast.For, i: int) -> Run:
        it = self.it
        match = self.structure.for_next.get(i)
        if match is None:
            return fail(errors.FOR_NEXT_UNMATCH, "FOR without NEXT")
        next_index, k = match
        counter = s.counter.name
        put = self.setter(s.counter)
        start = self.exprs.value(s.start)
        end = self.exprs.value(s.end)
        step = self.exprs.value(s.step) if s.step is not None else (lambda: 1)
        loops = it.loops
        from melfa.sim.interp.interpreter import Loop

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
                it.pc = next_index + 1  # zero-trip: on after the NEXT (and its other loops)
                handler = it.next_handlers.get(next_index)
                if handler is not None:
                    handler(k + 1)
                return
            if len(loops) >= errors.MAX_LOOP_DEPTH:
                raise errors.RunError(errors.NESTING_OVER, "FOR/WHILE nested deeper than 16")
            loops.append(Loop(i, counter, b, d))

        return run

    def _next(self, s: ast.Next, i: int) -> Run:
        it = self.it
        names: list[str | None] = [c.name for c in s.counters] or [None]
        setters = {c.name: self.setter(c) for c in s.counters}
        store = it.vars
        loops = it.loops

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
                    it.pc = loop.start + 1
                    return
                loops.pop()

        it.next_handlers[i] = run_from
        return lambda: run_from(0)

    def _while(self, s: ast.While, i: int) -> Run:
        it = self.it
        cond = self.exprs.cond(s.condition)
        wend = self.structure.while_wend.get(i)
        if wend is None:
            return fail(errors.WHILE_WEND_UNMATCH, "WHILE without WEND")
        loops = it.loops
        after = wend + 1
        from melfa.sim.interp.interpreter import Loop

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
                it.pc = after

        return run

    def _wend(self, s: ast.Wend, i: int) -> Run:
        it = self.it
        start = self.structure.wend_while.get(i)
        if start is None:
            return fail(errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
        loops = it.loops

        def run() -> None:
            if not loops or loops[-1].start != start:
                raise errors.RunError(errors.WHILE_WEND_UNMATCH, "WEND without WHILE")
            it.pc = start

        return run

    def _select(self, s: ast.Select, i: int) -> Run:
        it = self.it
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
                    it.pc = dest
                    return
            it.pc = default if default is not None else after

        return run

    def it_stmt(self, index: int) -> ast.Statement | None:
        return self._stmts[index]

    def _case_test(self, c: ast.Case) -> Callable[[Value], bool]:
        from melfa.sim.interp.exprs import compare

        lo = self.exprs.value(c.value)
        if c.kind is ast.CaseKind.RANGE and c.high is not None:
            hi = self.exprs.value(c.high)
            return lambda v: compare(ast.BinaryOp.GE, v, lo()) and compare(ast.BinaryOp.LE, v, hi())
        op = c.op if c.kind is ast.CaseKind.IS and c.op is not None else ast.BinaryOp.EQ
        return lambda v: compare(op, v, lo())

    def _break(self, s: ast.Break, i: int) -> Run:
        it = self.it
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
        loops = it.loops

        def run() -> None:
            if kind != "SELECT":
                for j in range(len(loops) - 1, -1, -1):
                    if loops[j].start == opener:
                        del loops[j:]
                        break
            it.pc = dest

        return run

    def _wait(self, s: ast.Wait, i: int) -> Run:
        it = self.it
        cond = self.exprs.cond(s.condition)
        from melfa.sim.interp.interpreter import WaitCond

        def run() -> None:
            if not cond():
                it.block = WaitCond(cond)

        return run

    def _defvar(self, s: ast.DefVar, i: int) -> Run:
        it = self.it
        store = it.vars
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
        return _nothing  # registered program-wide by _declare

    def _defplt(self, s: ast.DefPlt, i: int) -> Run:
        it = self.it
        num = self.exprs.value(s.number)
        pts = [self.exprs.value(e, VarType.POSITION) for e in (s.start, s.end_a, s.end_b)]
        diag = self.exprs.value(s.diagonal, VarType.POSITION) if s.diagonal is not None else None
        ca = self.exprs.value(s.count_a)
        cb = self.exprs.value(s.count_b)
        direction = self.exprs.value(s.direction)
        from melfa.sim.interp.interpreter import PalletDef

        def pos(f: Thunk) -> Position:
            v = f()
            if isinstance(v, Joints):
                v = it.robot.to_position(v)
            if not isinstance(v, Position):
                raise errors.RunError(errors.TYPE_COMBINATION, "DEF PLT needs positions")
            return v

        def run() -> None:
            n = integer(num(), "DEF PLT")
            if not 1 <= n <= 8:
                raise errors.RunError(
                    errors.ARGUMENT_OUT_OF_RANGE, f"pallet number {n} is not 1..8"
                )
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
            it.pallets[n] = PalletDef(
                pos(pts[0]), pos(pts[1]), pos(pts[2]), pos(diag) if diag else None, na, nb, d
            )

        return run

    def _defact(self, s: ast.DefAct, i: int) -> Run:
        it = self.it
        prio = self.exprs.value(s.priority)
        cond = self.exprs.cond(s.condition)
        dest = self.target(s.target)
        gosub = s.kind is ast.JumpKind.GOSUB
        mode = s.mode.upper() if s.mode else None
        from melfa.sim.interp.interpreter import ActDef

        def run() -> None:
            n = integer(prio(), "DEF ACT")
            if not 1 <= n <= 8:
                raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"ACT priority {n} is not 1..8")
            if isinstance(dest, errors.RunError):
                raise errors.RunError(errors.JUMP_DESTINATION_MISSING, dest.message)
            old = it.acts.get(n)
            it.acts[n] = ActDef(n, cond, gosub, dest, mode, old.enabled if old else False)

        return run

    def _actset(self, s: ast.ActSet, i: int) -> Run:
        it = self.it
        num = self.exprs.value(s.number)
        value = self.exprs.value(s.value)

        def run() -> None:
            n = integer(num(), "ACT")
            on = integer(value(), "ACT") != 0
            if n == 0:
                it.acts_master = on
                return
            act = it.acts.get(n)
            if act is None:
                raise errors.RunError(errors.VARIABLE_NOT_DEFINED, f"ACT {n} has no DEF ACT {n}")
            act.enabled = on

        return run

    def _dim(self, s: ast.Dim, i: int) -> Run:
        it = self.it
        from melfa.sim.interp.interpreter import MAX_DIM_SIZE, Array

        specs = []
        for a in s.arrays:
            sizes = [self.exprs.value(e) for e in a.sizes]
            name = a.name.name
            specs.append((name, sizes, it.types.get(name) or implied_type(name)))

        def run() -> None:
            for name, sizes, vtype in specs:
                if name in it.arrays:
                    raise errors.RunError(errors.DUPLICATE_DEFINITION, f"{name} is already DIMmed")
                dims = tuple(integer(f(), "DIM") for f in sizes)
                if not 1 <= len(dims) <= 3 or any(not 1 <= d <= MAX_DIM_SIZE for d in dims):
                    raise errors.RunError(
                        errors.ARRAY_ELEMENT, f"DIM {name}: 1 to 3 sizes of 1..{MAX_DIM_SIZE}"
                    )
                it.arrays[name] = Array(dims, vtype)

        return run

    def _print(self, s: ast.Print, i: int) -> Run:
        it = self.it
        items = [self.exprs.value(e) for e in s.items]

        def run() -> None:
            from melfa.sim.interp.builtins import format_number

            parts = []
            for f in items:
                v = f()
                parts.append(format_number(v) if isinstance(v, int | float) else str(v))
            it.console.append(",".join(parts))

        return run

    def _invalid(self, s: ast.InvalidStatement, i: int) -> Run:
        return fail(errors.SYNTAX_ERROR, f"syntax error: {s.issue.message}")

    def _refused(self, s: ast.Statement, i: int) -> Run:
        kind = type(s).__name__.upper()
        return fail(errors.NOT_SUPPORTED, f"{kind} is not supported by the simulator")

    def _noop(self, s: ast.Statement, i: int) -> Run:
        return _nothing


def _nothing() -> None:
    return None


def _raiser(exc: errors.RunError) -> Run:
    def run() -> None:
        raise errors.RunError(exc.number, exc.message)

    return run


def _refuse_set(message: str) -> Setter:
    def put(_v: Value) -> None:
        raise errors.RunError(errors.SYNTAX_ERROR, message)

    return put


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
    ast.Input: Compiler._refused,
    ast.OnCom: Compiler._refused,
    ast.ComControl: Compiler._refused,
    ast.InvalidStatement: Compiler._invalid,
}
