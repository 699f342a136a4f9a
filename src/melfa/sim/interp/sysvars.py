"""Robot status (system) variables: ``P_CURR``, ``M_IN(n)``, ``M_TIMER(n)`` … [S2e], §6.

`SystemVariables.getter(name, args)` gives a closure reading the variable (None when the
name is not a system variable, so it is an ordinary user/global variable like ``M_01``);
`setter` gives one that writes it (None: not a system variable). Which variables exist and
which a program may assign is the language's knowledge (`melfa.lang.model`).
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Callable, Sequence

from melfa.lang.model import SYSTEM_VARIABLES
from melfa.sim.interp import errors
from melfa.sim.interp.io import IOState
from melfa.sim.interp.robot import RobotPort, set_speed
from melfa.sim.interp.state import ProgramState
from melfa.sim.interp.values import Position, Value, round_half_away, type_name

Thunk = Callable[[], Value]
Setter = Callable[[Value], None]

TIMER_UNIT_S = 1.0
"""[GUESS] M_TIMER counts seconds (the doc's example ``M_TIMER(1)>10.5``); V manuals say ms."""

HAND_CHECK_MEANS_CLOSED = True
"""[GUESS] M_HNDCQ(n) reads 1 while hand n is closed (gripping), 0 while open."""

#: Bits read or written from the index on, per I/O variable (the language's fact).
IO_WIDTHS = {v.name: v.io_width for v in SYSTEM_VARIABLES.values() if v.io_width}

#: Status variables that exist on the controller but mean nothing in the simulator; reading
#: one stops with a clear message rather than an invented value.
UNSUPPORTED = frozenset({"P_SAFE", "M_RSPD", "M_MRATIO", "M_PSA", "M_TOOL", "M_DIN", "M_DOUT"})


def _num(value: Value, what: str) -> int:
    if isinstance(value, int | float):
        return round_half_away(value)
    raise errors.RunError(
        errors.TYPE_COMBINATION, f"{what} needs a number, not a {type_name(value)}"
    )


class SystemVariables:
    """The status variables of one slot, bound to its program state, arm and I/O."""

    def __init__(self, state: ProgramState, robot: RobotPort, io: IOState) -> None:
        self.state = state
        self.robot = robot
        self.io = io
        self.timers: dict[int, tuple[float, float]] = {}  # n -> (set at, value then)
        self.clock_origin = dt.datetime(2024, 1, 1)

    def reset(self) -> None:
        self.timers.clear()

    # ------------------------------------------------------------------ reading
    def getter(self, name: str, args: Sequence[Thunk]) -> Thunk | None:
        if len(name) < 2 or name[1] != "_":
            return None
        st = self.state
        robot = self.robot
        width = IO_WIDTHS.get(name)
        if width is not None:
            idx = self._one_arg(name, args)
            io = self.io
            if name.startswith("M_IN"):
                if width == 1:
                    return lambda: io.input(self._bit(idx()))
                return lambda: io.read_inputs(self._bit(idx()), width)
            if width == 1:
                return lambda: io.output(self._bit(idx()))
            return lambda: io.read_outputs(self._bit(idx()), width)
        if name == "M_TIMER":
            idx = self._one_arg(name, args)
            return lambda: self.timer(_num(idx(), "M_TIMER"))
        if name == "M_HNDCQ":
            idx = self._one_arg(name, args)

            def hand() -> Value:
                state = robot.hand_open(_num(idx(), "M_HNDCQ"))
                closed = state is False
                return 1 if closed == HAND_CHECK_MEANS_CLOSED else 0

            return hand
        simple: dict[str, Thunk] = {
            "P_CURR": robot.position,
            "J_CURR": robot.joints,
            "P_TOOL": robot.tool,
            "P_BASE": robot.base,
            "P_NTOOL": lambda: Position(fl1=0),
            "P_NBASE": lambda: Position(fl1=0),
            "M_SVO": lambda: 1 if robot.servo_on else 0,
            "M_RUN": lambda: 1 if st.is_running else 0,
            "M_WAI": lambda: 1 if st.waiting else 0,
            "M_ERR": lambda: 1 if st.caution is not None else 0,
            "M_ERRNO": lambda: st.caution.number if st.caution is not None else 0,
            "M_SKIPCQ": lambda: st.skipped,
            "M_OVRD": lambda: robot.speeds()[0],
            "M_JOVRD": lambda: robot.speeds()[1],
            "M_SPD": lambda: robot.speeds()[2],
            "M_OPOVRD": lambda: robot.speeds()[3],
            "M_NOVRD": lambda: 100,
            "M_NJOVRD": lambda: 100,
            "M_NSPD": robot.default_speed,
            "C_TIME": lambda: (self.clock_origin + dt.timedelta(seconds=st.now)).strftime(
                "%H:%M:%S"
            ),
            "C_DATE": lambda: (self.clock_origin + dt.timedelta(seconds=st.now)).strftime(
                "%Y/%m/%d"
            ),
        }
        fn = simple.get(name)
        if fn is not None:
            # P_CURR(1), M_RUN(1), M_SVO(1): the mechanism/slot number is accepted and ignored
            return fn
        if name in UNSUPPORTED:

            def unsupported() -> Value:
                raise errors.RunError(
                    errors.NOT_SUPPORTED, f"{name} is not supported by the simulator"
                )

            return unsupported
        return None

    # ------------------------------------------------------------------ writing
    def setter(self, name: str, args: Sequence[Thunk]) -> Setter | None:
        if len(name) < 2 or name[1] != "_":
            return None
        known = SYSTEM_VARIABLES.get(name)
        if known is not None and not known.assignable:
            return self._read_only(name)
        st = self.state
        robot = self.robot
        width = IO_WIDTHS.get(name)
        if width is not None:
            idx = self._one_arg(name, args)
            io = self.io
            if width == 1:
                return lambda v: io.set_output(self._bit(idx()), _num(v, name) & 1)
            return lambda v: io.write_outputs(self._bit(idx()), width, _num(v, name))
        if name == "M_TIMER":
            idx = self._one_arg(name, args)

            def set_timer(v: Value) -> None:
                if not isinstance(v, int | float):
                    raise errors.RunError(errors.TYPE_COMBINATION, "M_TIMER needs a number")
                self.timers[_num(idx(), "M_TIMER")] = (st.now, float(v))

            return set_timer
        if name == "P_TOOL":
            return lambda v: robot.set_tool(_position(v, name))
        if name == "P_BASE":
            return lambda v: robot.set_base(_position(v, name))
        if name == "M_OVRD":
            return lambda v: set_speed(robot, "OVRD", v)
        if name == "M_JOVRD":
            return lambda v: set_speed(robot, "JOVRD", v)
        if name in ("M_SPD", "M_NSPD"):
            return lambda v: set_speed(robot, "SPD", v)
        if self.getter(name, args) is not None:
            return self._read_only(name)
        return None

    def timer(self, n: int) -> float:
        set_at, value = self.timers.get(n, (0.0, 0.0))
        return value + (self.state.now - set_at) / TIMER_UNIT_S

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _read_only(name: str) -> Setter:
        def refuse(_v: Value) -> None:
            raise errors.RunError(errors.TYPE_COMBINATION, f"{name} is read-only")

        return refuse

    @staticmethod
    def _one_arg(name: str, args: Sequence[Thunk]) -> Thunk:
        if len(args) != 1:

            def bad() -> Value:
                raise errors.RunError(errors.SYNTAX_ERROR, f"{name} needs one number in ( )")

            return bad
        return args[0]

    @staticmethod
    def _bit(value: Value) -> int:
        n = _num(value, "an I/O number")
        if n < 0:
            raise errors.RunError(errors.ARGUMENT_OUT_OF_RANGE, f"I/O number {n} is negative")
        return n


def _position(value: Value, name: str) -> Position:
    if isinstance(value, Position):
        return value
    raise errors.RunError(errors.TYPE_COMBINATION, f"{name} needs a position")
