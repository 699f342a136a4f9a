"""Statements that drive the arm or the program's timing: MOV/MVS (close and appended
forms), the arcs, MVA, and the command statements (speeds, hand, TOOL/BASE, DLY, END,
HLT, ERROR, SERVO).

They reach the arm only through `RobotPort` (program units), so they never see
degrees or kin's types; a move blocks the program through `Interpreter.start_motion`.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.lang import ast
from melfa.protocol.limits import HANDS, span_text
from melfa.sim.interp import errors, posmath
from melfa.sim.interp.robot import ArcKind, set_speed
from melfa.sim.interp.state import Delay
from melfa.sim.interp.stmt_base import CompilerBase, Run, fail, integer, nothing, number
from melfa.sim.interp.values import Joints, Position, Value, VarType, type_name

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


class MotionStatements(CompilerBase):
    """Moves and robot/timing commands."""

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
        st = self.st
        act = a.action
        if isinstance(act, ast.Command) and act.kind is ast.CommandKind.SKIP:
            action: Run = it.skip_motion
        elif isinstance(act, ast.Command) and act.kind is ast.CommandKind.HLT:

            def action() -> None:
                it.halt(st.now)

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
        st = self.st
        robot = it.robot
        k = s.kind
        args = [self.exprs.value(a) if a is not None else None for a in s.args]
        if k in IGNORED_COMMANDS:
            return nothing
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
            return lambda: set_speed(robot, what, first())
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
                if n not in HANDS:
                    raise errors.RunError(
                        errors.ARGUMENT_OUT_OF_RANGE,
                        f"hand number must be {span_text(HANDS)}, got {n}",
                    )
                robot.set_hand(n, opening, st.now)

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
            return st.hold
        if k is ast.CommandKind.DLY:

            def delay() -> None:
                t = arg(0, "a time in seconds")
                if t < 0:
                    raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, "DLY time is negative")
                st.block = Delay(st.now + t)

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
                st.caution = None

            return reset_err
        if k is ast.CommandKind.CLR:
            return nothing
        return fail(errors.NOT_SUPPORTED, f"{k.value} is not supported by the simulator")

    def _switch(self, s: ast.Switch, i: int) -> Run:
        if s.kind is not ast.SwitchKind.SERVO:
            return nothing
        it = self.it
        st = self.st
        on = s.on
        return lambda: it.robot.set_servo(on, st.now)
