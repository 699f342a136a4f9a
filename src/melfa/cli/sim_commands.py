"""`melfa sim`: run the virtual CR2B-574 on a pseudo-terminal or a TCP port, or run one
program on the simulated arm and print its trace (`--run PROGRAM.MB4`, no robot, no port).

Thin on purpose: options are parsed here, the work is in `melfa.sim` (the trace in
`melfa.sim.interp.cli_trace`); `build_controller` and `serve_pty` / `serve_tcp` are reusable.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from pathlib import Path
from types import FrameType
from typing import Annotated

import typer
from rich.console import Console

from melfa.cli import EXIT_INTERRUPTED
from melfa.cli.checking import FileKind, UsageError, read_text_file
from melfa.cli.start_options import FeedOption, JointsOption, PoseOption, ServoOnOption
from melfa.cli.typer_app import app
from melfa.link.settings import BAUDRATES
from melfa.sim import NO_PACING, Pacing, PtyServer, SimConfig, TcpServer, VirtualController
from melfa.sim.config import DEFAULT_REPLY_LATENCY_S, KeySwitch, Terminator, strict_by_default
from melfa.sim.interp.cli_trace import run_and_trace
from melfa.sim.interp.fast import DEFAULT_MAX_TIME_S
from melfa.sim.interp.io import parse_input
from melfa.sim.interp.start import RunStart

console = Console(highlight=False, soft_wrap=True, emoji=False)  # never cut at 80 columns
errors = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)


def build_controller(
    *,
    jog: bool = True,
    key: KeySwitch = KeySwitch.AUTO_EXT,
    digits: int = 9,
    strict: bool | None = None,
    origin: bool = True,
    cterm: Terminator = Terminator.CR,
    open_required: bool = False,
) -> VirtualController:
    """The controller `melfa sim` serves; `strict=None` follows `$MELFA_SIM_STRICT`."""
    if digits not in (4, 9):
        raise ValueError(f"--digits {digits}: refusals have 4 (manual) or 9 (real) digits")
    config = SimConfig(
        jog_supported=jog,
        key=key,
        nine_digit_errors=digits == 9,
        origin_set=origin,
        strict=strict_by_default() if strict is None else strict,
        cterm=cterm,
        open_required=open_required,
    )
    return VirtualController(config)


def describe(config: SimConfig) -> str:
    """One line on what the served controller will do that a plain one does not."""
    notes = [f"MODE key {config.key.label}"]
    notes.append("9-digit refusals" if config.nine_digit_errors else "4-digit refusals")
    if config.strict:
        notes.append("strict: only commands a real controller was seen to answer")
    if not config.origin_set:
        notes.append("origin not set: positions ****, motion refused with L5150")
    if not config.jog_supported:
        notes.append("JOG refused (L2030)")
    if config.cterm is Terminator.CRLF:
        notes.append("replies end in CR LF (CTERM232=1)")
    if config.open_required:
        notes.append("OPEN required first")
    return "; ".join(notes)


def parse_host_port(text: str) -> tuple[str, int]:
    """`HOST:PORT` or `:PORT` or `PORT` -> (host, port); ValueError with what is wrong.

    >>> parse_host_port("127.0.0.1:10001"), parse_host_port(":0"), parse_host_port("5000")
    (('127.0.0.1', 10001), ('127.0.0.1', 0), ('127.0.0.1', 5000))
    """
    host, _, port = text.rpartition(":")
    if not port.isdigit() or not 0 <= int(port) <= 65535:
        raise ValueError(f"{text!r} is not HOST:PORT (port 0–65535; 0 picks a free one)")
    return host or "127.0.0.1", int(port)


def run_program(
    program: Path,
    points: Path | None,
    fast: bool,
    inputs: dict[int, int],
    max_time: float,
    start: RunStart,
) -> int:
    """`--run`: the trace on stdout; a closed pipe (`| head`) ends it quietly."""
    try:
        code = run_and_trace(
            program, points, fast, sys.stdout, max_time=max_time, inputs=inputs, start=start
        )
        sys.stdout.flush()
    except BrokenPipeError:
        # The reader went away: nothing more to say, and Python must not complain at exit.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    return code


def _until_interrupted(stop: threading.Event) -> None:
    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        while not stop.wait(0.2):
            pass
    finally:
        signal.signal(signal.SIGTERM, previous)


def serve_pty(
    controller: VirtualController,
    pacing: Pacing,
    stop: threading.Event,
    baud: int = 9600,
    link: Path | None = None,
) -> None:
    """Hand out one fresh pty after another until `stop` (or Ctrl-C); with ``link`` a
    symlink at that path always points at the pty being served (a stable device name)."""
    with PtyServer(controller, pacing=pacing) as server:

        def announce(path: str) -> None:
            if link is not None:
                tmp = link.with_name(link.name + ".tmp")
                tmp.unlink(missing_ok=True)
                tmp.symlink_to(path)
                tmp.replace(link)  # atomic: a client never finds the name missing
            shown = f"{link} -> {path}" if link is not None else path
            console.print(f"virtual CR2B-574 listening on [bold]{shown}[/] ({baud} 8E2)")
            console.print(f"  {describe(controller.config)}")
            console.print(
                "  one client per pty: when it disconnects, a fresh pty is served"
                + (f" behind {link}" if link is not None else " and its path printed here")
            )

        worker = threading.Thread(target=server.serve_forever, args=(announce,), daemon=True)
        worker.start()
        try:
            _until_interrupted(stop)
        finally:
            if link is not None and link.is_symlink():
                link.unlink()


def serve_tcp(
    controller: VirtualController,
    pacing: Pacing,
    host: str,
    port: int,
    stop: threading.Event,
    baud: int = 9600,
) -> None:
    """Serve on TCP until `stop` (or Ctrl-C)."""
    with TcpServer(controller, host=host, port=port, pacing=pacing) as server:
        console.print(
            f"virtual CR2B-574 listening on [bold]{server.url}[/] (one client at a time; "
            f"paced as {baud} 8E2)"
        )
        console.print(f"  {describe(controller.config)}")
        console.print(f"  connect with: melfa <command> --robot {server.url}")
        _until_interrupted(stop)


@app.command()
def sim(
    pty: Annotated[
        bool, typer.Option("--pty", help="Serve on a fresh pseudo-terminal (the default).")
    ] = False,
    tcp: Annotated[
        str | None,
        typer.Option("--tcp", metavar="HOST:PORT", help="Serve on TCP instead (port 0: any)."),
    ] = None,
    baud: Annotated[
        int, typer.Option("--baud", help="Line speed the pacing reproduces (8E2).")
    ] = 9600,
    no_pacing: Annotated[
        bool, typer.Option("--no-pacing", help="Reply at once, not at line speed.")
    ] = False,
    latency: Annotated[
        float,
        typer.Option(
            "--latency",
            metavar="S",
            help="Controller processing time before each reply (measured 0.1-0.15 s).",
        ),
    ] = DEFAULT_REPLY_LATENCY_S,
    no_jog: Annotated[
        bool,
        typer.Option("--no-jog", help="Refuse JOG with L2030, as a CR2B that does not take it."),
    ] = False,
    key: Annotated[
        KeySwitch,
        typer.Option(
            "--key",
            help="Where the MODE key stands: outside auto-ext, CNTLON is accepted but "
            "operation (RUN, SLOTINIT, SRVON…) is refused with 6020, as on the real one.",
        ),
    ] = KeySwitch.AUTO_EXT,
    digits: Annotated[
        int,
        typer.Option("--digits", help="Refusals with 9 digits (real CRn-5xx) or 4 (manual)."),
    ] = 9,
    strict: Annotated[
        bool | None,
        typer.Option(
            "--strict/--lenient",
            help="Refuse every command no real controller was seen to answer "
            "(default: $MELFA_SIM_STRICT, else lenient).",
        ),
    ] = None,
    no_origin: Annotated[
        bool,
        typer.Option("--no-origin", help="Origin lost: positions read ****, motion raises L5150."),
    ] = False,
    cterm: Annotated[
        Terminator,
        typer.Option(
            "--cterm",
            help="CTERM232: replies end in CR (0, factory) or CR LF (1, what clients that "
            "read lines, such as ctu-mitsubishi, need). Requests may end in either, or none.",
        ),
    ] = Terminator.CR,
    open_required: Annotated[
        bool,
        typer.Option(
            "--open-required",
            help="Refuse everything before OPEN= with 6010, as the manual says; real "
            "controllers answered clients that never sent it.",
        ),
    ] = False,
    link: Annotated[
        Path | None,
        typer.Option(
            "--link",
            metavar="PATH",
            help="With --pty: keep a symlink at PATH to the pty being served (a stable "
            "name for MELFA_ROBOT, as a fresh pty is served after every client).",
        ),
    ] = None,
    run: Annotated[
        Path | None,
        typer.Option(
            "--run",
            metavar="PROGRAM.MB4",
            help="Run this program on the simulated arm and print its trace (no server).",
        ),
    ] = None,
    points: Annotated[
        Path | None,
        typer.Option("--points", metavar="FILE.POS", help="Points file for --run."),
    ] = None,
    fast: Annotated[
        bool, typer.Option("--fast", help="With --run: as fast as possible, not in real time.")
    ] = False,
    inputs: Annotated[
        list[str] | None,
        typer.Option(
            "--input",
            metavar="N=V",
            help="With --run: set input signal M_IN(N) to V (0/1) first; repeatable.",
        ),
    ] = None,
    max_time: Annotated[
        float,
        typer.Option("--max-time", metavar="S", help="With --run: stop after S simulated seconds."),
    ] = DEFAULT_MAX_TIME_S,
    servo_on: ServoOnOption = False,
    joints: JointsOption = None,
    pose: PoseOption = None,
    feed: FeedOption = None,
) -> None:
    """Run the virtual CR2B-574 controller until Ctrl-C, or trace one program (--run)."""
    if pty and tcp is not None:
        errors.print("[red]error:[/] choose one of --pty and --tcp")
        raise typer.Exit(2)
    if run is not None:
        if pty or tcp is not None:
            errors.print("[red]error:[/] --run traces a program; it does not serve --pty/--tcp")
            raise typer.Exit(2)
        if max_time <= 0:
            errors.print(f"[red]error:[/] --max-time {max_time:g} must be > 0 seconds")
            raise typer.Exit(2)
        settings: dict[int, int] = {}
        for text in inputs or []:
            try:
                bit, value = parse_input(text)
            except ValueError as exc:
                errors.print(f"[red]error:[/] --input {exc}")
                raise typer.Exit(2) from None
            settings[bit] = value
        try:
            start = RunStart.parse(servo_on, joints, feed, pose)
            # The one reader's rules (extension, not binary) before the run reads them.
            read_text_file(run, FileKind.PROGRAM)
            if points is not None:
                read_text_file(points, FileKind.POINTS)
        except (ValueError, UsageError) as exc:
            errors.print(f"[red]error:[/] {exc}")
            raise typer.Exit(2) from None
        raise typer.Exit(run_program(run, points, fast, settings, max_time, start))
    for name, given in (
        ("--points", points is not None),
        ("--fast", fast),
        ("--input", bool(inputs)),
        ("--max-time", max_time != DEFAULT_MAX_TIME_S),
        ("--servo-on", servo_on),
        ("--joints", joints is not None),
        ("--pose", pose is not None),
        ("--feed", bool(feed)),
    ):
        if given:
            errors.print(f"[red]error:[/] {name} goes with --run PROGRAM.MB4")
            raise typer.Exit(2)
    if link is not None and tcp is not None:
        errors.print("[red]error:[/] --link names a pty; it does not go with --tcp")
        raise typer.Exit(2)
    if baud not in BAUDRATES:
        errors.print(f"[red]error:[/] --baud {baud} is not one of {', '.join(map(str, BAUDRATES))}")
        raise typer.Exit(2)
    if latency < 0:
        errors.print(f"[red]error:[/] --latency {latency} must be ≥ 0 seconds")
        raise typer.Exit(2)
    pacing = NO_PACING if no_pacing else Pacing.for_baud(baud, latency)
    try:
        controller = build_controller(
            jog=not no_jog,
            key=key,
            digits=digits,
            strict=strict,
            origin=not no_origin,
            cterm=cterm,
            open_required=open_required,
        )
    except ValueError as exc:
        errors.print(f"[red]error:[/] {exc}")
        raise typer.Exit(2) from None
    stop = threading.Event()
    try:
        if tcp is not None:
            try:
                host, port = parse_host_port(tcp)
            except ValueError as exc:
                errors.print(f"[red]error:[/] --tcp {exc}")
                raise typer.Exit(2) from None
            serve_tcp(controller, pacing, host, port, stop, baud)
        else:
            serve_pty(controller, pacing, stop, baud, link)
    except KeyboardInterrupt:  # Ctrl-C (SIGTERM ends it with status 0): stopped cleanly
        console.print("virtual controller stopped")
        raise typer.Exit(EXIT_INTERRUPTED) from None
    except OSError as exc:
        errors.print(f"[red]error:[/] cannot serve: {exc.strerror or exc}")
        raise typer.Exit(3) from None
    console.print("virtual controller stopped")
