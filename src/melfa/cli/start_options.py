"""How a simulated run starts (`melfa sim --run` and `melfa debug`): the options once, so the
two commands offer the same words for `sim.interp.start.RunStart`."""

from __future__ import annotations

from typing import Annotated

import typer

ServoOnOption = Annotated[
    bool, typer.Option("--servo-on", help="Start with the servo on (as a program left it).")
]
JointsOption = Annotated[
    str | None,
    typer.Option("--joints", metavar="J1,…,J6", help="Start the arm at these joints (degrees)."),
]
PoseOption = Annotated[
    str | None,
    typer.Option(
        "--pose",
        metavar="X,Y,Z,A,B,C[,FL1,FL2]",
        help="Start the arm at this position (mm, degrees; solved to joints).",
    ),
]
FeedOption = Annotated[
    list[str] | None,
    typer.Option("--feed", metavar="N=TEXT", help="A line for the program's INPUT #N; repeatable."),
]

__all__ = ["FeedOption", "JointsOption", "PoseOption", "ServoOnOption"]
