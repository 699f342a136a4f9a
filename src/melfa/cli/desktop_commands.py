"""`melfa desktop`: the small Qt client (the thesis's RQt frontend) for a running `melfa serve`.

Qt is an optional extra (`pip install melfa[desktop]`): nothing here imports it until the
command runs, so `import melfa.cli` stays Qt-free, and a missing PySide6 is one clear line.
"""

from __future__ import annotations

import importlib.util
import os
import sys
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

from melfa.cli.typer_app import app

EXIT_USAGE = 2
INSTALL_HINT = "pip install 'melfa[desktop]'"

_err = Console(stderr=True, highlight=False, soft_wrap=True, emoji=False)


def qt_available() -> bool:
    """True when PySide6 (with QtWidgets) can be imported."""
    try:
        return importlib.util.find_spec("PySide6.QtWidgets") is not None
    except (ImportError, ValueError):
        return False


def no_display() -> bool:
    """On Linux, True when there is no display to open a window on (Qt would abort)."""
    if not sys.platform.startswith("linux"):
        return False
    return not any(os.environ.get(v) for v in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"))


@app.command()
def desktop(
    server: Annotated[
        str,
        typer.Option("--server", "-s", help="The melfa server's address (see `melfa serve`)."),
    ] = "http://127.0.0.1:8080",
    user: Annotated[
        str, typer.Option("--user", "-u", help="Username to sign in with (asked otherwise).")
    ] = "",
) -> None:
    """Open the desktop client: load, run, send instructions, watch the robot, STOP."""
    from melfa.desktop.api import normalize_server

    try:
        address = normalize_server(server)
    except ValueError as exc:
        _err.print(f"[bold red]error:[/] {escape(str(exc))}")
        raise typer.Exit(EXIT_USAGE) from None
    if not qt_available():
        _err.print(
            "[bold red]error:[/] the desktop client needs PySide6, which is not installed.\n"
            f"Install it with: [bold]{escape(INSTALL_HINT)}[/]"
        )
        raise typer.Exit(EXIT_USAGE)
    if no_display():
        _err.print(
            "[bold red]error:[/] melfa desktop opens a window, and there is no display here "
            "(DISPLAY is not set). Run it in a desktop session, or over `ssh -X`."
        )
        raise typer.Exit(EXIT_USAGE)
    try:
        from melfa.desktop.app import main
    except ImportError as exc:  # PySide6 present but broken (e.g. missing system libraries)
        _err.print(
            f"[bold red]error:[/] cannot start Qt: {escape(str(exc))}\n"
            f"Reinstall with: [bold]{escape(INSTALL_HINT)}[/]"
        )
        raise typer.Exit(EXIT_USAGE) from None
    code = main(address, user)
    if code:
        raise typer.Exit(code)
