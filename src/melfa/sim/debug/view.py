"""What a debugger shows of a program's state: values as MELFA writes them, and the
variables panel (numbers, strings, positions, joints, arrays, I/O, the arm).

A position prints as the controller writes it, ``(+400.00,+0.00,+645.00,+180.00,+0.00,
+180.00)(7,0)`` (mm and degrees, structure flags), a joint position as ``(+0.00,…)``
(degrees), a real without trailing zeros (``2.5``), a string in quotes.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from melfa.protocol.limits import HANDS
from melfa.sim.interp.builtins import format_number
from melfa.sim.interp.errors import RunError
from melfa.sim.interp.io import IOState
from melfa.sim.interp.robot import RobotPort
from melfa.sim.interp.state import Array, ProgramState
from melfa.sim.interp.sysvars import SystemVariables
from melfa.sim.interp.values import Joints, Position, Value


def melfa_text(value: Value) -> str:
    """A value as MELFA writes it.

    >>> melfa_text(42), melfa_text(2.5), melfa_text("OK")
    ('42', '2.5', '"OK"')
    >>> melfa_text(Position.from_degrees((400, 0, 645, 180, 0, 180)))
    '(+400.00,+0.00,+645.00,+180.00,+0.00,+180.00)(7,0)'
    """
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, int | float):
        return format_number(value)
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, Position):
        cells = ",".join(_signed(v) for v in value.to_degrees())
        return f"({cells})({value.fl1},{value.fl2})"
    return "(" + ",".join(_signed(v) for v in value.to_degrees()) + ")"


def _signed(v: float) -> str:
    """``+12.30``; never ``-0.00``."""
    text = f"{v:+.2f}"
    return "+0.00" if text == "-0.00" else text


class VarKind(enum.Enum):
    """The panel's groups, in the order it shows them."""

    NUMBER = "number"
    STRING = "string"
    POSITION = "position"
    JOINT = "joint"
    ARRAY = "array"
    INPUT = "input"
    OUTPUT = "output"
    ROBOT = "robot"


@dataclass(frozen=True, slots=True)
class VarView:
    """One row of the variables panel; `changed` marks a value the last step changed."""

    name: str
    kind: VarKind
    value: str
    changed: bool = False
    elements: tuple[VarView, ...] = ()  # an array's elements that have a value

    def to_json(self) -> dict[str, object]:
        return {
            "name": self.name,
            "kind": self.kind.value,
            "value": self.value,
            "changed": self.changed,
            "elements": [e.to_json() for e in self.elements],
        }


def _kind(value: Value) -> VarKind:
    if isinstance(value, str):
        return VarKind.STRING
    if isinstance(value, Position):
        return VarKind.POSITION
    if isinstance(value, Joints):
        return VarKind.JOINT
    return VarKind.NUMBER


def _array(name: str, arr: Array) -> VarView:
    sizes = ",".join(str(n) for n in arr.sizes)
    elements = tuple(
        VarView(f"{name}({','.join(str(i) for i in key)})", _kind(v), melfa_text(v))
        for key, v in sorted(arr.data.items())
    )
    return VarView(name, VarKind.ARRAY, f"DIM {name}({sizes})", elements=elements)


ROBOT_VARIABLES = ("P_CURR", "J_CURR", "M_SVO", "M_OVRD", "M_JOVRD", "M_SPD", "M_OPOVRD")
"""The arm's state the panel always shows: where it is, servo, the speed settings."""


def snapshot(
    state: ProgramState, sysvars: SystemVariables, robot: RobotPort, io: IOState
) -> list[VarView]:
    """Every variable with a value, grouped by `VarKind` then sorted by name (unmarked)."""
    rows = [VarView(name, _kind(v), melfa_text(v)) for name, v in state.vars.items()]
    rows += [_array(name, arr) for name, arr in state.arrays.items()]
    rows += [VarView(f"M_IN({bit})", VarKind.INPUT, "1") for bit in sorted(io.inputs())]
    rows += [VarView(f"M_OUT({bit})", VarKind.OUTPUT, "1") for bit in sorted(io.outputs())]
    for name in ROBOT_VARIABLES:
        read = sysvars.getter(name, ())
        if read is None:
            continue
        try:
            rows.append(VarView(name, VarKind.ROBOT, melfa_text(read())))
        except RunError as exc:
            rows.append(VarView(name, VarKind.ROBOT, f"({exc.message})"))
    for hand in HANDS:
        is_open = robot.hand_open(hand)
        if is_open is not None:
            rows.append(VarView(f"HAND {hand}", VarKind.ROBOT, "open" if is_open else "closed"))
    order = list(VarKind)
    robot_order = {n: i for i, n in enumerate(ROBOT_VARIABLES)}
    return sorted(
        rows,
        key=lambda r: (
            order.index(r.kind),
            robot_order.get(r.name, len(robot_order)) if r.kind is VarKind.ROBOT else 0,
            r.name,
        ),
    )


def mark_changes(rows: list[VarView], before: dict[str, VarView]) -> list[VarView]:
    """`rows` with `changed` set where the value differs from `before` (or is new)."""
    out = []
    for r in rows:
        old = before.get(r.name)
        if old is None or old.value != r.value or old.elements != r.elements:
            elements = tuple(
                VarView(e.name, e.kind, e.value, True)
                if e not in (old.elements if old else ())
                else e
                for e in r.elements
            )
            out.append(VarView(r.name, r.kind, r.value, True, elements))
        else:
            out.append(r)
    return out
