"""The `melfa` command line.

Commands are thin: they parse options, call the library, and print. Every user mistake
becomes one clear message and an exit code, never a traceback:

    0  done
    1  refused: errors in a program, or the controller said no
    2  usage: bad options, missing or unreadable file
    3  link failure or timeout
"""

from melfa.cli.app import app

# The command modules register on `app` when imported; `app` imports them on demand
# (`melfa check` loads only the language toolkit), see melfa.cli.app.


def main() -> None:
    """Entry point of the `melfa` console script."""
    app()


__all__ = ["app", "main"]
