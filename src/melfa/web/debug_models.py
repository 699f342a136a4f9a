"""Request and reply bodies of the debugger API (`/api/debug`, docs/api.md "Debugger")."""

from __future__ import annotations

import enum
from typing import Annotated, Any

from pydantic import BaseModel, Field

from melfa.web.models import Input, ShortText, SourceIn


class DebugCommand(enum.Enum):
    """What the toolbar's buttons ask (docs/debugger.md "Commands")."""

    RUN = "run"
    CONTINUE = "continue"
    STEP = "step"
    STEP_OVER = "step-over"
    STEP_OUT = "step-out"
    PAUSE = "pause"


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
    "InputIn",
    "RunToIn",
    "SpeedIn",
]
