"""Interim `EXEC` executor: the statement forms public drivers send (protocol.md §3.4).

This is a stop-gap until the interpreter's `execute_statement` is wired in (one evaluator,
not two): it understands only what S6/S7/S16/S18/S19 send through EXEC —

- assignments of constants: `P1=(x,y,z,a,b,c)(fl1,fl2)`, `J1=(j1,…,j6)`
- `MOV`/`MVS` to a variable, a constant, or a relative target: `P_CURR*P1`, `P_CURR*(…)`,
  `P1*P_CURR`, `P_CURR+(…)`, `J_CURR+J1`, `J_CURR+(…)`
- `HOPEN n` / `HCLOSE n`, `SERVO ON|OFF`, `OVRD n`, `JOVRD n`, `SPD n`, `ACCEL [a[,b]]`,
  `TOOL (…)|P`, `BASE (…)|P|0`, `REM …` / `'…`
"""

from __future__ import annotations

import re

from melfa.kin import IDENTITY_POSE, Pose, pose_add, pose_mul
from melfa.sim.machine import ArmFault, InterimArm
from melfa.sim.runner import StepError

SYNTAX = 4220
UNDEFINED = 3700  # L3700 variable never initialised [melfa-basic-iv.md §8]
SERVO_OFF = 2000

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:E[-+]?\d+)?"
_CONST = re.compile(r"\(([^()]*)\)(?:\(\s*([^()]*)\s*\))?")
_ASSIGN = re.compile(r"([A-Z][A-Z0-9_]*)\s*=\s*(.+)")


class DirectExecutor:
    """Runs one EXEC statement on an `InterimArm`; raises `StepError` with the number."""

    def __init__(self, arm: InterimArm) -> None:
        self.arm = arm
        self.variables: dict[str, Pose | tuple[float, ...]] = {}
        self.speeds = {"OVRD": 100.0, "JOVRD": 100.0, "SPD": 0.0}

    def execute(self, statement: str, now: float) -> None:
        text = statement.strip()
        upper = text.upper()
        if not upper or upper.startswith(("REM", "'")):
            return
        word, _, rest = upper.partition(" ")
        rest = rest.strip()
        if word in ("MOV", "MVS"):
            self._move(rest, now)
        elif word in ("HOPEN", "HCLOSE"):
            hand = int(self._number(rest or "1"))
            if not 1 <= hand <= 8:
                raise StepError(3110, f"hand {hand} is not 1–8")
            self.arm.set_hand(hand, word == "HOPEN", now)
        elif word == "SERVO":
            if rest not in ("ON", "OFF"):
                raise StepError(SYNTAX, "SERVO needs ON or OFF")
            self.arm.set_servo(rest == "ON", now)
        elif word in ("OVRD", "JOVRD", "SPD"):
            self.speeds[word] = self._number(rest)
        elif word == "ACCEL":
            pass
        elif word in ("TOOL", "BASE"):
            value = IDENTITY_POSE if rest in ("0", "") else self._pose(rest)
            setattr(self.arm, word.lower(), value)
        elif (match := _ASSIGN.fullmatch(upper)) is not None:
            name, expr = match.groups()
            self.variables[name] = self._value(expr.strip(), joint=name.startswith("J"))
        else:
            raise StepError(SYNTAX, f"EXEC cannot run {statement!r} here")

    def _number(self, text: str) -> float:
        if not re.fullmatch(_NUM, text.strip()):
            raise StepError(SYNTAX, f"{text!r} is not a number")
        return float(text)

    def _constant(self, text: str, joint: bool) -> Pose | tuple[float, ...]:
        match = _CONST.fullmatch(text.replace(" ", ""))
        if match is None:
            raise StepError(SYNTAX, f"{text!r} is not a position constant")
        values = [float(v) if v else 0.0 for v in match.group(1).split(",")]
        if joint:
            return tuple((values + [0.0] * 6)[:6])
        flags = [int(f) for f in (match.group(2) or "7,0").split(",") if f] + [7, 0]
        x, y, z, a, b, c = (values + [0.0] * 6)[:6]
        return Pose(x, y, z, a, b, c, fl1=flags[0], fl2=flags[1])

    def _value(self, text: str, joint: bool) -> Pose | tuple[float, ...]:
        text = text.strip()
        if text.startswith("("):
            return self._constant(text, joint)
        if text == "P_CURR":
            return self.arm.pose
        if text == "J_CURR":
            return self.arm.joints
        for op in ("*", "+"):
            if op in text:
                left, right = (self._value(part, joint) for part in text.split(op, 1))
                if isinstance(left, Pose) and isinstance(right, Pose):
                    return pose_mul(left, right) if op == "*" else pose_add(left, right)
                if op == "+" and isinstance(left, tuple) and isinstance(right, tuple):
                    return tuple(a + b for a, b in zip(left, right, strict=True))
                raise StepError(3110, f"cannot combine {text!r}")
        if text not in self.variables:
            raise StepError(UNDEFINED, f"variable {text} has no value")
        return self.variables[text]

    def _pose(self, text: str) -> Pose:
        value = self._value(text, joint=False)
        if not isinstance(value, Pose):
            raise StepError(SYNTAX, f"{text!r} is not an XYZ position")
        return value

    def _move(self, rest: str, now: float) -> None:
        target = self._value(rest, joint=rest.startswith(("J", "(")) and "P" not in rest[:1])
        if not self.arm.servo:
            raise StepError(SERVO_OFF, "the servo is off")
        percent = self.speeds["OVRD"] * self.speeds["JOVRD"] / 100.0
        try:
            if isinstance(target, Pose):
                self.arm.move_pose(target, now, percent)
            else:
                self.arm.move_joint(target, now, percent)
        except ArmFault as fault:
            raise StepError(fault.number, str(fault), level="H") from None
