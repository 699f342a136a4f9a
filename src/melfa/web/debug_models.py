"""Request and reply bodies of the debugger API (`/api/debug`, docs/api.md "Debugger")."""

from __future__ import annotations

import enum
from typing import Annotated, Any

from pydantic import BaseModel, Field, model_validator

from melfa.protocol.limits import OVERRIDE_PERCENT
from melfa.vocab.start import StartPlace, StartServo
from melfa.web.models import Input, ShortText, SourceIn


class DebugCommand(enum.Enum):
    """What the toolbar's buttons ask (docs/debugger.md "Commands")."""

    RUN = "run"
    CONTINUE = "continue"
    STEP = "step"
    STEP_OVER = "step-over"
    STEP_OUT = "step-out"
    PAUSE = "pause"


class PoseIn(Input):
    """A position in XYZ: mm and degrees, with its structure flags."""

    x: float
    y: float
    z: float
    a: float = 0.0
    b: float = 0.0
    c: float = 0.0
    fl1: Annotated[int, Field(ge=0, le=7)] = 7
    fl2: Annotated[int, Field(ge=0)] | None = Field(
        default=None, description="J6's turn (None: the turn nearest the simulator's)."
    )


class FeedLineIn(Input):
    """A line the program's ``INPUT #file`` reads."""

    file: Annotated[int, Field(ge=1)]
    line: Annotated[str, Field(max_length=127)]


class StartIn(Input):
    """How the run starts (docs/ide.md "Debugging"); words in `melfa.vocab.start`."""

    servo: StartServo = StartServo.AS_IT_IS
    place: StartPlace = StartPlace.AS_IT_STANDS
    joints: Annotated[list[float], Field(min_length=6, max_length=6)] | None = Field(
        default=None, description="J1…J6 in degrees, with ``place: joints``."
    )
    pose: PoseIn | None = Field(default=None, description="With ``place: pose``: solved to joints.")
    override: Annotated[int, Field(ge=OVERRIDE_PERCENT.start, le=OVERRIDE_PERCENT[-1])] | None = (
        Field(default=None, description="The OP override (%); None: as the simulator's.")
    )
    feed: list[FeedLineIn] = Field(default_factory=list, max_length=64)

    @model_validator(mode="after")
    def _place_given(self) -> StartIn:
        if self.place is StartPlace.JOINTS and self.joints is None:
            raise ValueError("the arm starts at joint angles: give the six joints")
        if self.place is StartPlace.POSE and self.pose is None:
            raise ValueError("the arm starts at a position: give X, Y, Z, A, B, C")
        return self


class DebugStartIn(SourceIn):
    """The program (from the body, else the workspace) with its breakpoints and inputs."""

    lines: list[Annotated[int, Field(ge=1, le=100_000)]] = Field(
        default_factory=list, description="Breakpoints on these lines of the program."
    )
    labels: list[ShortText] = Field(
        default_factory=list, description="Breakpoints on these labels (`*PICK` or `PICK`)."
    )
    speed: ShortText = Field("real", description="`real`, `instant` or `xN` (e.g. `x4`).")
    inputs: dict[Annotated[int, Field(ge=0, le=32767)], Annotated[int, Field(ge=0, le=1)]] = Field(
        default_factory=dict, description="`M_IN(n)` values to set before running."
    )
    start: StartIn = Field(default_factory=lambda: StartIn(), description="How the run starts.")


class BreakpointsIn(Input):
    lines: list[Annotated[int, Field(ge=1, le=100_000)]] = Field(default_factory=list)
    labels: list[ShortText] = Field(default_factory=list)


class RunToIn(Input):
    line: Annotated[int, Field(ge=1, le=100_000)]


class InputIn(Input):
    bit: Annotated[int, Field(ge=0, le=32767)]
    value: Annotated[int, Field(ge=0, le=1)]


class SpeedIn(Input):
    speed: ShortText = Field(description="`real`, `instant` or `xN` (e.g. `x4`).")


class EvaluateIn(Input):
    expression: ShortText


class EvaluateOut(BaseModel):
    expression: str
    value: str = Field(description="As MELFA writes it (positions `(x,y,z,a,b,c)(fl1,fl2)`).")


class DebugOut(BaseModel):
    """The engine's status (`state`, `location` {line, step, source}, `time`, `waiting`,
    `speed`, `stop` {reason, location, time, error, breakpoint}, `breakpoints`) and the
    variables panel (rows `{name, kind, value, changed, elements}`)."""

    session: int = Field(description="Which debug session (each starts `seq` again).")
    seq: int = Field(description="Grows with every change; show the highest seen.")
    status: dict[str, Any]
    variables: list[dict[str, Any]]
    program: str = Field(description="The text under the debugger (the editor compares).")


__all__ = [
    "BreakpointsIn",
    "DebugCommand",
    "DebugOut",
    "DebugStartIn",
    "EvaluateIn",
    "EvaluateOut",
    "FeedLineIn",
    "InputIn",
    "PoseIn",
    "RunToIn",
    "SpeedIn",
    "StartIn",
]
