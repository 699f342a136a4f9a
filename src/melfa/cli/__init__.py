"""The `melfa` command line.

Commands are thin: they parse options, call the library, and print. Every user mistake
becomes one clear message and an exit code, never a traceback:

    0  done
    1  refused: errors in a program, or the controller said no
    2  usage: bad options, missing or unreadable file
    3  link failure or timeout
  130  interrupted (Ctrl-C): whatever was moving or serving was stopped first, one line
       says so, and no traceback is shown
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from melfa.cli.typer_app import OnDemandTyper

# The command modules register on `app` when imported; `app` imports them on demand, see
# melfa.cli.typer_app. `app` itself (Typer) is imported on first use, for start-up time:
# `import melfa.cli` stays light, so `melfa check` (melfa.cli.checking) never loads Typer.


def __getattr__(name: str) -> Any:
    if name == "app":
        from melfa.cli.typer_app import app  # Typer loads only when the command line needs it

        return app
    raise AttributeError(name)


EXIT_INTERRUPTED = 130
"""Ctrl-C, as a shell reports a program ended by SIGINT (128 + 2), for every command."""


def main() -> None:
    """Entry point of the `melfa` console script."""
    try:
        raise SystemExit(_run(sys.argv[1:]))
    except KeyboardInterrupt:
        sys.stderr.write("interrupted\n")
        raise SystemExit(EXIT_INTERRUPTED) from None


def _run(args: list[str]) -> int:
    if args[:1] == ["check"]:
        # `melfa check` runs without Typer or the other commands, for start-up time.
        from melfa.cli.checking import check_main

        return check_main(args[1:])
    from melfa.cli.typer_app import app

    app(prog_name="melfa")  # Typer ends a Ctrl-C in a command with status 130 itself
    return 0


app: OnDemandTyper
__all__ = ["app", "main"]
