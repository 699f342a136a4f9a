"""What the debugger says: its speeds, run states, stops, breakpoints, error reports and
the status a view draws, each with its JSON (`to_json`) for the web and the `melfa debug`
console. `melfa.sim.debug.engine.Debugger` makes them; nothing here runs a program.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

from melfa.protocol.error_table import ERROR_MESSAGES, error_code
from melfa.sim.runner import RunnerError

__all__ = [
    "INSTANT",
    "REAL_TIME",
    "Breakpoint",
    "DebugError",
    "ErrorReport",
    "Frame",
    "Location",
    "RunState",
    "Speed",
    "Status",
    "Stop",
    "StopReason",
    "error_report",
]


class DebugError(ValueError):
    """A debugger request that cannot be done, in the user's words (no such line, …)."""


@dataclass(frozen=True, slots=True)
class Speed:
    """How simulated time follows the clock: `factor` simulated seconds per clock second,
    or None for as fast as possible."""

    factor: float | None = 1.0

    @classmethod
    def times(cls, n: float) -> Speed:
        if not n > 0:
            raise DebugError(f"a speed factor must be more than 0, got {n}")
        return cls(float(n))

    @classmethod
    def parse(cls, text: str) -> Speed:
        """``real`` (or ``1``), ``instant``, ``x4`` / ``4`` / ``0.5``.

        >>> Speed.parse("x4"), Speed.parse("instant"), Speed.parse("real")
        (Speed(factor=4.0), Speed(factor=None), Speed(factor=1.0))
        """
        t = text.strip().lower()
        if t in ("instant", "fast", "max"):
            return INSTANT
        if t in ("real", "realtime", "real-time"):
            return REAL_TIME
        try:
            return cls.times(float(t.removeprefix("x").removeprefix("×")))
        except ValueError:
            raise DebugError(f"{text!r} is not a speed (real, instant, or x N)") from None

    @property
    def text(self) -> str:
        if self.factor is None:
            return "instant"
        return "real time" if self.factor == 1.0 else f"x{self.factor:g}"


REAL_TIME = Speed(1.0)
INSTANT = Speed(None)


class RunState(enum.Enum):
    IDLE = "idle"  # loaded, not started
    RUNNING = "running"  # running or waiting (`Debugger.waiting`)
    PAUSED = "paused"  # stopped at a breakpoint, a step, HLT or pause(); can continue
    FINISHED = "finished"
    FAILED = "failed"  # stopped by a run-time error


class StopReason(enum.Enum):
    BREAKPOINT = "breakpoint"
    STEP = "step"  # step, next, finish or run-to-cursor done
    PAUSE = "pause"  # pause() asked for it
    HLT = "hlt"  # the program's own HLT
    END = "end"
    ERROR = "error"
    TIME_LIMIT = "time-limit"
    BUSY = "busy"  # an endless loop with no move, DLY or WAIT (instant speed only)


@dataclass(frozen=True, slots=True)
class Location:
    """A statement of the user's text: its 1-based `line`, the controller's step number
    for it, and the text of the line."""

    line: int
    step: int | None
    source: str

    def to_json(self) -> dict[str, object]:
        return {"line": self.line, "step": self.step, "source": self.source}


@dataclass(frozen=True, slots=True)
class ErrorReport:
    """A run-time error: the controller's number and text, and what the simulator found."""

    number: int
    level: str  # H (servo off), L (the program stops), C (caution)
    code: str  # "L3700"
    message: str  # the controller's message for the number
    explanation: str  # in plain words: "variable M9 has no value"
    location: Location

    @property
    def text(self) -> str:
        """``L3700 Undefined (uninitialised) variable: variable M9 has no value``."""
        if self.explanation and self.explanation != self.message:
            return f"{self.code} {self.message}: {self.explanation}"
        return f"{self.code} {self.message}"

    def to_json(self) -> dict[str, object]:
        return {
            "number": self.number,
            "level": self.level,
            "code": self.code,
            "message": self.message,
            "explanation": self.explanation,
            "text": self.text,
            "location": self.location.to_json(),
        }


@dataclass(frozen=True, slots=True)
class Stop:
    """Why and where the program stopped, at which simulated time."""

    reason: StopReason
    location: Location
    time: float
    error: ErrorReport | None = None
    breakpoint: int | None = None  # the breakpoint's id when one was hit

    def to_json(self) -> dict[str, object]:
        return {
            "reason": self.reason.value,
            "location": self.location.to_json(),
            "time": self.time,
            "error": self.error.to_json() if self.error else None,
            "breakpoint": self.breakpoint,
        }


@dataclass(frozen=True, slots=True)
class Breakpoint:
    """A breakpoint: on `line` of the user's text (a label's breakpoint has `label` too)."""

    id: int
    line: int
    label: str | None = None

    def to_json(self) -> dict[str, object]:
        return {"id": self.id, "line": self.line, "label": self.label}


@dataclass(frozen=True, slots=True)
class Frame:
    """One level of the GOSUB stack: where it is (innermost first) and how it got there."""

    location: Location
    depth: int
    interrupt: int | None = None  # the DEF ACT priority when entered by an interrupt


@dataclass(frozen=True, slots=True)
class Status:
    """Everything a view needs after a poll (JSON with `to_json`)."""

    state: RunState
    location: Location | None
    time: float
    waiting: bool
    speed: Speed
    stop: Stop | None
    breakpoints: tuple[Breakpoint, ...] = field(default_factory=tuple)

    def to_json(self) -> dict[str, object]:
        return {
            "state": self.state.value,
            "location": self.location.to_json() if self.location else None,
            "time": self.time,
            "waiting": self.waiting,
            "speed": self.speed.text,
            "stop": self.stop.to_json() if self.stop else None,
            "breakpoints": [b.to_json() for b in self.breakpoints],
        }


def error_report(err: RunnerError, location: Location) -> ErrorReport:
    """The controller's number and message for `err`, with the simulator's explanation."""
    known = ERROR_MESSAGES.get(err.number)
    message = known.message if known is not None else err.message
    code = error_code(err.number, err.level)
    return ErrorReport(err.number, err.level.letter, code, message, err.message, location)
