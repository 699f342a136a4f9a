"""`melfa sim`: run the virtual CR2B-574 on a pseudo-terminal or a TCP port.

Thin on purpose: options are parsed here, the work is in `melfa.sim`. To add an option
(the interpreter's `--run PROGRAM.MB4`), add a parameter to `sim` and a branch before the
server starts; `build_controller` and `serve_pty` / `serve_tcp` are reusable.
"""

from __future__ import annotations

import signal
import threading
from types import FrameType
from typing import Annotated

import typer
from rich.console import Console

from melfa.cli.app import app
from melfa.link.settings import BAUDRATES
from melfa.sim import NO_PACING, Pacing, PtyServer, SimConfig, TcpServer, VirtualController
from melfa.sim.config import DEFAULT_REPLY_LATENCY_S

console = Console(highlight=False)
errors = Console(stderr=True, highlight=False)


def build_controller(*, jog: bool = True) -> VirtualController:
    """The controller `melfa sim` serves."""
    return VirtualController(SimConfig(jog_supported=jog))


def parse_host_port(text: str) -> tuple[str, int]:
    """`HOST:PORT` or `:PORT` or `PORT` -> (host, port); ValueError with what is wrong.

    >>> parse_host_port("127.0.0.1:10001"), parse_host_port(":0"), parse_host_port("5000")
    (('127.0.0.1', 10001), ('127.0.0.1', 0), ('127.0.0.1', 5000))
    """
    host, _, port = text.rpartition(":")
    if not port.isdigit() or not 0 <= int(port) <= 65535:
        raise ValueError(f"{text!r} is not HOST:PORT (port 0–65535; 0 picks a free one)")
    return host or "127.0.0.1", int(port)


def _until_interrupted(stop: threading.Event) -> None:
    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        while not stop.wait(0.2):
            pass
    except KeyboardInterrupt:
        pass
    finally:
        signal.signal(signal.SIGTERM, previous)


def serve_pty(controller: VirtualController, pacing: Pacing, stop: threading.Event) -> None:
    """Hand out one fresh pty after another until `stop` (or Ctrl-C)."""
    with PtyServer(controller, pacing=pacing) as server:

        def announce(path: str) -> None:
            console.print(f"virtual CR2B-574 listening on [bold]{path}[/] (9600 8E2)")
            console.print(
                "  one client per pty: when it disconnects, the next pty path is printed here"
            )

        worker = threading.Thread(target=server.serve_forever, args=(announce,), daemon=True)
        worker.start()
        _until_interrupted(stop)


def serve_tcp(
    controller: VirtualController, pacing: Pacing, host: str, port: int, stop: threading.Event
) -> None:
    """Serve on TCP until `stop` (or Ctrl-C)."""
    with TcpServer(controller, host=host, port=port, pacing=pacing) as server:
        console.print(f"virtual CR2B-574 listening on [bold]{server.url}[/] (one client at a time)")
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
) -> None:
    """Run the virtual CR2B-574 controller until Ctrl-C."""
    if pty and tcp is not None:
        errors.print("[red]error:[/] choose one of --pty and --tcp")
        raise typer.Exit(2)
    if baud not in BAUDRATES:
        errors.print(f"[red]error:[/] --baud {baud} is not one of {', '.join(map(str, BAUDRATES))}")
        raise typer.Exit(2)
    if latency < 0:
        errors.print(f"[red]error:[/] --latency {latency} must be ≥ 0 seconds")
        raise typer.Exit(2)
    pacing = NO_PACING if no_pacing else Pacing.for_baud(baud, latency)
    controller = build_controller(jog=not no_jog)
    stop = threading.Event()
    try:
        if tcp is not None:
            try:
                host, port = parse_host_port(tcp)
            except ValueError as exc:
                errors.print(f"[red]error:[/] --tcp {exc}")
                raise typer.Exit(2) from None
            serve_tcp(controller, pacing, host, port, stop)
        else:
            serve_pty(controller, pacing, stop)
    except KeyboardInterrupt:
        pass  # Ctrl-C before the wait loop started: same clean stop
    except OSError as exc:
        errors.print(f"[red]error:[/] cannot serve: {exc.strerror or exc}")
        raise typer.Exit(3) from None
    console.print("virtual controller stopped")
