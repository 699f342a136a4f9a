"""The `melfa` command line.

Commands are thin: they parse options, call the library, and print. Every user mistake
becomes one clear message and an exit code, never a traceback:

    0  done
    1  refused: errors in a program, or the controller said no
    2  usage: bad options, missing or unreadable file
    3  link failure or timeout
"""

from melfa.cli.app import app

# Each module registers its commands on `app` when imported.
from melfa.cli import lang_commands as _lang_commands  # noqa: F401  # isort: skip
from melfa.cli import robot_commands as _robot_commands  # noqa: F401  # isort: skip
from melfa.cli import sim_commands as _sim_commands  # noqa: F401  # isort: skip
from melfa.cli import debug_commands as _debug_commands  # noqa: F401  # isort: skip
from melfa.cli import users_commands as _users_commands  # noqa: F401  # isort: skip
from melfa.cli import serve_commands as _serve_commands  # noqa: F401  # isort: skip
from melfa.cli import ros_commands as _ros_commands  # noqa: F401  # isort: skip
from melfa.cli import desktop_commands as _desktop_commands  # noqa: F401  # isort: skip


def main() -> None:
    """Entry point of the `melfa` console script."""
    app()


__all__ = ["app", "main"]
