"""What `Robot.status` reports: STATE and the active alarm, read once, as plain values."""

from __future__ import annotations

from dataclasses import dataclass

from melfa.protocol import ErrorLevel, State
from melfa.protocol.answers import RunStatus, StopStatus
from melfa.robot.errors import describe


@dataclass(frozen=True)
class Alarm:
    """An active controller error: number, level (if the controller said) and its text."""

    number: int
    message: str
    level: ErrorLevel | None = None

    @property
    def detail(self) -> str:
        """``L2600 Position data exceeds the limit``."""
        return describe(self.number, self.message)


@dataclass(frozen=True)
class ControllerStatus:
    """One ``STATE`` (program, line, override, status bits, error) plus ``ERRORMES``."""

    state: State
    alarm: Alarm | None

    @property
    def running(self) -> bool:
        """The RUN bit [DOC S1 p.55]."""
        return RunStatus.RUNNING in self.state.status.run

    @property
    def servo_on(self) -> bool:
        """The servo bit [DOC S1 p.55]."""
        return RunStatus.SERVO_ON in self.state.status.run

    @property
    def waiting(self) -> bool:
        """The program waits (WAIT statement) [DOC S1 p.55]."""
        return StopStatus.WAIT in self.state.status.stop

    @property
    def run_state(self) -> str:
        """``running``, ``waiting`` or ``stopped``."""
        if self.running:
            return "waiting" if self.waiting else "running"
        return "stopped"

    def to_json(self) -> dict[str, object]:
        """A JSON-ready dictionary (for ``melfa status --json``)."""
        return {
            "run": self.run_state,
            "program": self.state.program or None,
            "line": self.state.line,
            "servo": self.servo_on,
            "override": self.state.override,
            "alarm": None
            if self.alarm is None
            else {
                "number": self.alarm.number,
                "level": self.alarm.level.letter if self.alarm.level else None,
                "text": self.alarm.detail,
            },
        }
