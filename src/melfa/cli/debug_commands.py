"""``melfa debug PROGRAM.MB4``: the gdb-like debugger on a simulated RV-6S.

Thin: options and files here; the console is `melfa.sim.debug.console`, the engine
`melfa.sim.debug.engine` (docs/debugger.md). Commands come from the terminal with a prompt,
or one per line from stdin when it is not a terminal (scripts, tests). Exit code: 0, or 1
when the program cannot be loaded or the last run stopped with a run-time error, 2 usage.
"""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console as RichConsole

from melfa.cli.checking import FileKind, UsageError, read_text_file
from melfa.cli.start_options import FeedOption, JointsOption, PoseOption, ServoOnOption
from melfa.cli.typer_app import app
from melfa.sim.debug.cell import Cell, CellError
from melfa.sim.debug.cell_templates import TEMPLATES, template
from melfa.sim.debug.console import Console
from melfa.sim.debug.engine import DEFAULT_MAX_TIME_S, DebugError, Debugger, Speed
from melfa.sim.debug.preflight import preflight, report_text
from melfa.sim.interp.io import parse_input
from melfa.sim.interp.start import RunStart

errors = RichConsole(stderr=True, highlight=False, soft_wrap=True, emoji=False)

REAL_TIME_TICK_S = 0.02
"""How long the console sleeps between polls while a run goes on in real time."""


def _read(path: Path, what: str) -> str:
    try:
        return path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        errors.print(f"[red]error:[/] cannot read {what} {path}: {exc.strerror or exc}")
        raise typer.Exit(2) from None


def _read_source(path: Path, kind: FileKind) -> str:
    """A program or points file, read as every command reads one (`read_text_file`)."""
    try:
        return read_text_file(path, kind).text
    except UsageError as exc:
        errors.print(f"[red]error:[/] {exc}")
        raise typer.Exit(2) from None


@app.command()
def debug(
    program: Annotated[Path, typer.Argument(metavar="PROGRAM.MB4", help="The program to debug.")],
    points: Annotated[
        Path | None, typer.Option("--points", metavar="FILE.POS", help="Its points file.")
    ] = None,
    inputs: Annotated[
        list[str] | None,
        typer.Option(
            "--input", metavar="N=V", help="Set input signal M_IN(N) to V (0/1) first; repeatable."
        ),
    ] = None,
    speed: Annotated[
        str,
        typer.Option(
            "--speed", metavar="SPEED", help="instant (the default), real, or xN (N times real)."
        ),
    ] = "instant",
    preflight_only: Annotated[
        bool,
        typer.Option(
            "--preflight",
            help="Print the pre-flight report of a simulated run and exit (1 if it has errors).",
        ),
    ] = False,
    cell_path: Annotated[
        Path | None,
        typer.Option(
            "--cell",
            metavar="CELL.json",
            help="The cell (table, fixtures, parts, gripper…; docs/simulator.md), or a "
            "template's name: thesis-bench.",
        ),
    ] = None,
    max_time: Annotated[
        float,
        typer.Option("--max-time", metavar="S", help="Stop a run after S simulated seconds."),
    ] = DEFAULT_MAX_TIME_S,
    servo_on: ServoOnOption = False,
    joints: JointsOption = None,
    pose: PoseOption = None,
    feed: FeedOption = None,
) -> None:
    """Debug a program on a simulated RV-6S: break, step, next, finish, print, info vars…"""
    settings: list[tuple[int, int]] = []
    for text in inputs or []:
        try:
            settings.append(parse_input(text))
        except ValueError as exc:
            errors.print(f"[red]error:[/] --input {exc}")
            raise typer.Exit(2) from None
    try:
        pace = Speed.parse(speed)
    except DebugError as exc:
        errors.print(f"[red]error:[/] --speed {exc}")
        raise typer.Exit(2) from None
    if max_time <= 0:
        errors.print(f"[red]error:[/] --max-time {max_time:g} must be > 0 seconds")
        raise typer.Exit(2)
    try:
        start = RunStart.parse(servo_on, joints, feed, pose)
    except ValueError as exc:
        errors.print(f"[red]error:[/] {exc}")
        raise typer.Exit(2) from None
    cell = None
    if cell_path is not None:
        try:
            if not cell_path.exists() and str(cell_path) in TEMPLATES:
                cell = template(str(cell_path))
            else:
                cell = Cell.from_json(_read(cell_path, "the cell"))
        except CellError as exc:
            errors.print(f"[red]error:[/] {cell_path}: {exc}")
            raise typer.Exit(2) from None
    text = _read_source(program, FileKind.PROGRAM)
    points_text = _read_source(points, FileKind.POINTS) if points is not None else ""
    try:
        debugger = Debugger(
            text,
            points_text,
            clock=time.monotonic,
            speed=pace,
            max_time=max_time,
            arm=start.arm(),
        )
    except DebugError as exc:
        errors.print(f"[red]error:[/] {program}: cannot run: {exc}")
        raise typer.Exit(1) from None
    start.apply(debugger.interp)
    for bit, value in settings:
        debugger.set_input(bit, value)
    if preflight_only:
        report = preflight(text, debugger.points, cell=cell, inputs=settings, max_time=max_time)
        sys.stdout.write(report_text(report, program.name))
        raise typer.Exit(0 if report.ok else 1)
    console = Console(debugger, sys.stdout, idle=lambda: time.sleep(REAL_TIME_TICK_S), cell=cell)
    interactive = sys.stdin.isatty()
    if interactive:
        # Line editing and history at the prompt; imported only for a terminal (it is slow
        # to load and changes how input() behaves).
        with contextlib.suppress(ImportError):
            import readline  # noqa: F401
        print(f"{program.name}: {len(debugger.lines)} lines; help lists the commands")
    while True:
        try:
            line = input("(melfa) ") if interactive else sys.stdin.readline()
        except EOFError:
            break
        if not interactive and not line:
            break  # end of the script
        try:
            if not console.execute(line):
                break
        except KeyboardInterrupt:
            stop = debugger.pause()
            print("interrupted")
            if stop is not None:
                print(f"stopped at line {stop.location.line}: {stop.location.source}")
        sys.stdout.flush()
    raise typer.Exit(1 if console.failed else 0)
