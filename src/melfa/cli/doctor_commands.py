"""`melfa doctor`: probe the controller before the first day with the real arm.

Read-only unless ``--probe-upload``; prints each item as ok / refused / unknown with the raw
reply when it is odd, writes the same report to a file a lab can send back (the byte trace
beside it), writes the settings it settled to the robot profile, and exits 0 usable, 1
something blocks use (TEACH or AUTO (Op.), an active alarm, the origin lost, STOP refused),
3 link failure.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from melfa.cli.robot_session import EXIT_LINK, EXIT_REFUSED, Target, _out, _session, robot_command
from melfa.robot.doctor import Verdict, diagnose
from melfa.robot.profile import save_profile

_STYLE = {Verdict.OK: "green", Verdict.REFUSED: "red", Verdict.UNKNOWN: "yellow"}
REPORT_FILE = Path("melfa-doctor.txt")
"""Where the report goes by default (the trace beside it, ``.trace``)."""


@robot_command(
    help="Probe the controller: banner, mode key, servo, alarms, origin, override, program "
    "1, operation rights, which STOP form and handshakes it accepts, its line parameters. "
    "Moves nothing and writes nothing to the controller unless --probe-upload (a scratch "
    "program is written, read back and deleted). Every answer is reported, odd ones with "
    "the raw reply. Writes the report to --report (melfa-doctor.txt) and every byte to a "
    "trace beside it, and saves what it found to the robot profile other commands and "
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
    report_file: Annotated[
        Path,
        typer.Option(
            "--report",
            metavar="FILE",
            help="Where to write the report (the byte trace goes beside it, FILE.trace, "
            "unless --trace says otherwise).",
        ),
    ] = REPORT_FILE,
    *,
    target: Target,
) -> None:
    """See the help text above."""
    trace = report_file.with_suffix(".trace")
    if target.trace is None:
        target = dataclasses.replace(target, trace=trace)
        trace.unlink(missing_ok=True)
    with _session(target) as robot:
        report = diagnose(robot, probe_upload=probe_upload)
    lines = [f"melfa doctor: {target.spec}", *report.render()]
    report_file.write_text("\n".join(lines) + "\n", encoding="utf-8")
    width = max(len(f.item) for f in report.findings)
    for finding in report.findings:
        style = _STYLE[finding.verdict]
        blocks = "  [bold red]blocks use[/]" if finding.blocks else ""
        raw = f"  [dim]reply: {escape(finding.raw)}[/]" if finding.raw else ""
        _out.print(
            f"{escape(finding.item):<{width}}  [{style}]{finding.verdict.value:<8}[/]  "
            f"{escape(finding.detail)}{blocks}{raw}"
        )
    if report.link_failure:
        _out.print(f"probing ended early: {escape(report.link_failure)}")
    if report.controller:
        path = save_profile(target.spec, report.settings, report.controller)
        found = ", ".join(f"{k}={v}" for k, v in sorted(report.settings.items()))
        _out.print(f"profile for {escape(target.spec)} written to {escape(str(path))}: {found}")
    where = f" (trace: {target.trace})" if target.trace is not None else ""
    _out.print(f"verdict: {report.verdict}; report written to {escape(str(report_file))}{where}")
    if report.link_failure:
        raise typer.Exit(EXIT_LINK)
    if report.blocked:
        raise typer.Exit(EXIT_REFUSED)


__all__ = ["EXIT_LINK", "doctor"]
