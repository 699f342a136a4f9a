"""`melfa serve`: the web IDE and its API, with the in-process virtual controller unless a
robot is given.

The command is thin: it opens the store (creating the first admin and printing its
password once), takes its ports (a busy one fails before anything says "serving"; port 0
is a free one, printed), builds the app (`melfa.web.create_app`) and runs it under uvicorn.
Ctrl+C shuts down cleanly: a program still running on the robot is stopped, the service
stops polling, ends the lease and closes the link; then "melfa stopped" and exit status
130, as every command's Ctrl-C (started with SIGINT ignored, by a script's ``&``, too).
SIGTERM, a service manager's stop, shuts down the same way and exits 0, as `melfa sim`.
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import ipaddress
import os
import signal
import socket
from collections.abc import Callable, Iterator
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Annotated

import typer
from rich.console import Console
from rich.markup import escape

from melfa.cli import EXIT_INTERRUPTED
from melfa.cli.typer_app import app
from melfa.link import ROBOT_ENV, RobotSpecError, parse_robot
from melfa.store import ADMIN_PASSWORD_ENV, ADMIN_USERNAME, DATA_ENV, Store, StoreError
from melfa.vocab.queue import TurnEnd

if TYPE_CHECKING:
    import uvicorn

EXIT_USAGE = 2

_out = Console(highlight=False, soft_wrap=True, emoji=False)
_err = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)


LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")


def _is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@app.command()
def serve(
    robot: Annotated[
        str | None,
        typer.Option(
            "--robot",
            "-r",
            help="Robot: a serial device, tcp://host:port, a pyserial URL, or sim "
            f"(default ${ROBOT_ENV}, else the in-process virtual controller).",
        ),
    ] = None,
    trace: Annotated[
        Path | None,
        typer.Option(
            "--trace",
            metavar="FILE",
            help="Record every byte to and from the robot, with timestamps, to FILE.",
        ),
    ] = None,
    host: Annotated[
        str, typer.Option("--host", help="Address to listen on (localhost unless told).")
    ] = "127.0.0.1",
    port: Annotated[
        int,
        typer.Option("--port", "-p", help="TCP port (0: a free one, printed).", min=0, max=65535),
    ] = 8080,
    data: Annotated[
        Path | None,
        typer.Option(
            "--data",
            help=f"Data directory holding melfa.sqlite3 (default ${DATA_ENV}, else ./data).",
            file_okay=False,
        ),
    ] = None,
    rosbridge_port: Annotated[
        int | None,
        typer.Option(
            "--rosbridge-port",
            help="Also serve rosbridge on this port (rosbridge_server's is 9090), at / and "
            "/rosbridge, for roslibjs pages that connect to ws://host:port.",
            min=1,
            max=65535,
        ),
    ] = None,
    rosbridge_mode: Annotated[
        str,
        typer.Option(
            "--rosbridge-mode",
            help="How that port's connections behave: melfa, or thesis (the thesis's "
            "execute node; ?mode= in the URL chooses per connection).",
        ),
    ] = "melfa",
    allowed_origins: Annotated[
        list[str] | None,
        typer.Option(
            "--allowed-origin",
            help="A browser origin (https://lab.example:8000) besides the server's own whose "
            "pages may use the sign-in cookie on WebSockets; repeatable.",
        ),
    ] = None,
    require_simulation: Annotated[
        bool,
        typer.Option(
            "--require-simulation",
            help="The instructor's gate: the lab robot loads and runs a program only after "
            "the same program and points passed a simulated run without pre-flight errors, "
            "whichever door it comes through (web, rosbridge, the thesis's messages). "
            "Without it, the gate the instructor's desk last saved; with it, on at start "
            "whatever was saved.",
        ),
    ] = False,
    lab_networks: Annotated[
        list[str] | None,
        typer.Option(
            "--lab-network",
            metavar="CIDR",
            help="Where the lab robot may be driven from: a network such as 192.168.10.0/24 "
            "(repeatable). Elsewhere students may watch and use their own simulator, and "
            "STOP always works; staff are exempt. Default: anywhere, or what the "
            "instructor's desk last saved (switched live there); with this option, a "
            "saved list is kept only inside these networks.",
        ),
    ] = None,
    turn_minutes: Annotated[
        float,
        typer.Option(
            "--turn-minutes",
            help="The lab robot's queue: how long a student's turn at the arm lasts.",
            min=0.5,
        ),
    ] = 4.0,
    claim_seconds: Annotated[
        float,
        typer.Option(
            "--claim-seconds",
            help="The queue: how long the arm is offered before a student moves back one place.",
            min=5.0,
        ),
    ] = 60.0,
    turn_end: Annotated[
        TurnEnd,
        typer.Option(
            "--turn-end",
            help="The queue: at a turn's end a running program is stopped, or may finish "
            "(nothing new starts).",
        ),
    ] = TurnEnd.STOP,
    private_idle: Annotated[
        float,
        typer.Option(
            "--private-idle",
            help="Free a student's private simulator after this many seconds unused.",
            min=1.0,
        ),
    ] = 1800.0,
    allowed_hosts: Annotated[
        list[str] | None,
        typer.Option(
            "--allowed-host",
            help="A host name the server answers to (lab.example); repeatable. Default: "
            "localhost, 127.0.0.1 and ::1 on a loopback address, any otherwise.",
        ),
    ] = None,
    trusted_proxies: Annotated[
        list[str] | None,
        typer.Option(
            "--trusted-proxy",
            help="Address of a reverse proxy whose X-Forwarded-For/-Proto are believed "
            "(none by default, not even localhost); repeatable. See docs/security.md.",
        ),
    ] = None,
) -> None:
    """Serve the web IDE and its API (docs at /docs)."""
    # Lazily (start-up): `melfa --help` imports this module; the web stack loads to serve only.
    import uvicorn

    from melfa.service.lab_network import NetworkError, parse_networks
    from melfa.service.queue import QueueSettings
    from melfa.web import WebSettings, create_app
    from melfa.web.logs import configure
    from melfa.web.pools import PoolSizes
    from melfa.web.server import uvicorn_config

    try:
        parsed = parse_robot(robot)
    except RobotSpecError as exc:
        _err.print(f"[bold red]error:[/] {escape(str(exc))}")
        raise typer.Exit(EXIT_USAGE) from None
    spec = parsed.text
    try:
        networks = parse_networks(lab_networks or ())
    except NetworkError as exc:
        _err.print(f"[bold red]error:[/] --lab-network: {escape(str(exc))}")
        raise typer.Exit(EXIT_USAGE) from None
    data_dir = data or Path(os.environ.get(DATA_ENV) or "data")
    configure()
    try:
        store = Store.open_dir(data_dir)
        generated = store.accounts.ensure_admin()
    except StoreError as exc:
        _err.print(f"[bold red]error:[/] {escape(str(exc))}")
        raise typer.Exit(EXIT_USAGE) from None
    if generated is not None:
        _out.print(
            f"Created the first account: [bold]{ADMIN_USERNAME}[/] with password "
            f"[bold]{escape(generated)}[/] (shown only this once; "
            f"set ${ADMIN_PASSWORD_ENV} to choose it)"
        )
    if not _is_loopback(host):
        _err.print(
            f"[bold yellow]warning:[/] listening on {escape(host)}: anyone who can reach "
            "this address can try to sign in and, once signed in, move the robot"
        )
    from melfa.web.routes.pages import VENDOR, vendor_ready

    if not vendor_ready():
        _err.print(
            f"[bold yellow]warning:[/] the browser IDE's libraries are missing ({VENDOR}); "
            "run scripts/setup (or scripts/build-frontend) to make them. The API works meanwhile."
        )
    hosts = tuple(allowed_hosts or ())
    if not hosts and _is_loopback(host):
        hosts = LOOPBACK_NAMES  # a page on another name (DNS rebinding) is refused
    settings = WebSettings(
        data_dir=data_dir,
        robot=spec,
        robot_trace=trace,
        allowed_origins=tuple(allowed_origins or ()),
        require_simulation=require_simulation,
        lab_networks=networks,
        queue=QueueSettings(claim_s=claim_seconds, turn_s=turn_minutes * 60, at_turn_end=turn_end),
        private_idle_s=private_idle,
        allowed_hosts=hosts,
        trusted_proxies=tuple(trusted_proxies or ()),
        pools=PoolSizes(cpu_processes=True),  # checks never hold the GIL against STOP
    )
    web_app = create_app(settings, store=store)
    config = uvicorn_config(
        web_app,
        host=host,
        port=port,
        limits=settings.limits,
        trusted_proxies=settings.trusted_proxies,
        log_level="warning",
        access_log=False,
        timeout_graceful_shutdown=3,
    )
    # The ports are taken here, before anything says "serving": a busy port fails first, and
    # --port 0 prints the port the system chose.
    sockets: list[socket.socket] = []
    for wanted in (port, rosbridge_port):
        if wanted is None:
            continue
        try:
            sockets.append(_listen(host, wanted))
        except OSError as exc:
            for taken in sockets:
                taken.close()
            store.close()
            why = (
                "is in use (another melfa serve, or rosbridge_server?); choose another"
                if exc.errno == errno.EADDRINUSE
                else f"cannot be listened on ({exc.strerror or exc})"
            )
            _err.print(f"[bold red]error:[/] port {wanted} on {escape(host)} {why}")
            raise typer.Exit(EXIT_USAGE) from None
    web_socket, *bridge_sockets = sockets
    robot_text = "virtual controller (in process)" if parsed.is_sim else spec
    shown = f"[{host}]" if ":" in host else host
    said = [
        f"melfa serving on http://{shown}:{_port_of(web_socket)}/  (robot: {escape(robot_text)})"
    ]
    served: list[tuple[uvicorn.Server, list[socket.socket]]] = [
        (uvicorn.Server(config), [web_socket])
    ]
    if rosbridge_port is not None:
        from melfa.web.rosbridge_app import create_rosbridge_app

        try:
            bridge = create_rosbridge_app(web_app, rosbridge_mode)
        except ValueError as exc:
            for taken in sockets:
                taken.close()
            store.close()
            _err.print(f"[bold red]error:[/] --rosbridge-mode: {escape(str(exc))}")
            raise typer.Exit(EXIT_USAGE) from None
        bridge_server = uvicorn.Server(
            uvicorn_config(
                bridge,
                host=host,
                port=rosbridge_port,
                limits=settings.limits,
                trusted_proxies=settings.trusted_proxies,
                log_level="warning",
                timeout_graceful_shutdown=3,
            )
        )
        served.append((bridge_server, bridge_sockets))
        bridge_port = _port_of(bridge_sockets[0])
        said.append(f"rosbridge on ws://{shown}:{bridge_port}/  (mode {rosbridge_mode})")

    def announce() -> None:
        for line in said:
            _out.print(line)

    try:
        with _stop_signals():
            asyncio.run(_serve_all(served, announce))
    except KeyboardInterrupt:
        # uvicorn re-raises Ctrl+C after its clean shutdown: said, then exit 130 (melfa.cli).
        _out.print("melfa stopped")
        raise typer.Exit(EXIT_INTERRUPTED) from None
    except _Terminated:
        pass  # a service manager's stop, after the same clean shutdown: exit 0
    finally:
        store.close()
        for taken in sockets:
            taken.close()
    _out.print("melfa stopped")


class _Terminated(Exception):
    """SIGTERM (a service manager's stop), re-raised by uvicorn after its clean shutdown."""


@contextlib.contextmanager
def _stop_signals() -> Iterator[None]:
    """SIGINT and SIGTERM each end the server as uvicorn does (a clean shutdown), whatever
    its parent set, and its status then says which: Ctrl-C 130, SIGTERM 0 (as `melfa sim`).

    uvicorn takes both while it serves and, once shut down, raises the signal again under
    the handler it found. A script's ``&`` starts a command with SIGINT ignored: the server
    still stopped on SIGINT but exited 0. And SIGTERM's default handler killed the process
    there, before its store was closed, with a warning about leaked semaphores; so SIGINT
    gets Python's usual handler and SIGTERM one that ends it like Ctrl-C, with status 0."""

    def terminated(signum: int, frame: FrameType | None) -> None:
        raise _Terminated

    before_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    before_term = signal.signal(signal.SIGTERM, terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before_int)
        signal.signal(signal.SIGTERM, before_term)


def _listen(host: str, port: int) -> socket.socket:
    """A socket bound to ``host:port`` (0: a free port the system chooses), as uvicorn
    binds its own; `OSError` when it cannot be had."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(2048)
    except OSError:
        sock.close()
        raise
    sock.set_inheritable(True)
    return sock


def _port_of(sock: socket.socket) -> int:
    return int(sock.getsockname()[1])


async def _serve_all(
    served: list[tuple[uvicorn.Server, list[socket.socket]]], announce: Callable[[], object]
) -> None:
    """Run the web server and the optional rosbridge server on one loop, each on its own
    sockets; the first one handles Ctrl+C, and when it ends the others end too.

    ``announce`` ("serving on …") is called once the first has started, when uvicorn's
    Ctrl+C handling is in place: a stop right after the line (a lab's service manager, a
    script) is then a clean stop, never a traceback from a loop that had not begun."""
    (first, first_sockets), *others = served
    for other, _ in others:
        other.capture_signals = contextlib.nullcontext  # type: ignore[method-assign,assignment]
    tasks = [asyncio.create_task(other.serve(sockets=socks)) for other, socks in others]
    herald = asyncio.create_task(_when_started(first, announce))
    shutdown = first.shutdown

    async def shutdown_all(sockets: list[socket.socket] | None = None) -> None:
        # The others end inside the first's shutdown, before its own (the rosbridge app
        # uses the web app's robot service): the first re-raises Ctrl+C once its shutdown
        # returns, and that cancels whatever is still running; a rosbridge server cut off
        # mid-shutdown printed tracebacks.
        for other, _ in others:
            other.should_exit = True
        await asyncio.gather(*tasks, return_exceptions=True)
        await shutdown(sockets)

    first.shutdown = shutdown_all  # type: ignore[method-assign]
    try:
        await first.serve(sockets=first_sockets)
    finally:
        herald.cancel()
        for other, _ in others:
            other.should_exit = True
        await asyncio.gather(herald, *tasks, return_exceptions=True)


async def _when_started(server: uvicorn.Server, announce: Callable[[], object]) -> None:
    """Call ``announce`` once ``server`` has started (uvicorn says so by a flag only)."""
    while not server.started:
        await asyncio.sleep(0.01)
    announce()
