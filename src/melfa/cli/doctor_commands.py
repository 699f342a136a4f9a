"""`melfa doctor`: probe the controller before the first day with the real arm.

Read-only unless ``--probe-upload``; prints each item as ok / refused / unknown, writes the
settings it settled to the robot profile, and exits 0 usable, 1 something blocks use (TEACH
mode, an active alarm), 3 link failure.
"""

from __future__ import annotations

from typing import Annotated

import typer
from rich.markup import escape

from melfa.cli.robot_session import EXIT_LINK, EXIT_REFUSED, Target, _out, _session, robot_command
from melfa.robot.doctor import Verdict, diagnose
from melfa.robot.profile import save_profile

_STYLE = {Verdict.OK: "green", Verdict.REFUSED: "red", Verdict.UNKNOWN: "yellow"}


@robot_command(
    help="Probe the controller: banner, mode key, servo, alarms, override, program 1, which "
    "STOP form and handshakes it accepts, its line parameters. Moves nothing and writes "
    "nothing to the controller unless --probe-upload (a scratch program is written, read "
    "back and deleted). Saves what it found to the robot profile other commands and "
    "`melfa serve` use. Exit 0 usable, 1 something blocks use, 3 link failure."
)
def doctor(
    probe_upload: Annotated[
        bool,
        typer.Option(
            "--probe-upload",
            help="Also write, read back and delete a scratch program (EMDAT limits, ';').",
        ),
    ] = False,
    *,
    target: Target,
) -> None:
    """See the help text above."""
    with _session(target) as robot:
        report = diagnose(robot, probe_upload=probe_upload)
    width = max(len(f.item) for f in report.findings)
    for finding in report.findings:
        style = _STYLE[finding.verdict]
        _out.print(
            f"{escape(finding.item):<{width}}  [{style}]{finding.verdict.value:<8}[/]  "
            f"{escape(finding.detail)}"
        )
    path = save_profile(target.spec, report.settings, report.controller)
    found = ", ".join(f"{k}={v}" for k, v in sorted(report.settings.items()))
    _out.print(f"profile for {escape(target.spec)} written to {escape(str(path))}: {found}")
    if report.blocked:
        raise typer.Exit(EXIT_REFUSED)


__all__ = ["EXIT_LINK", "doctor"]
