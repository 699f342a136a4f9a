"""The Typer application object every command module registers on, loading them on demand.

`melfa check` runs in editors and pre-commit hooks on every save, so it must not pay for
importing the simulator, the store, the web server or numpy. The application therefore knows
which module registers each command (`COMMAND_MODULES`) and, when run as ``melfa <command>``,
imports only that module. Anything else (``melfa --help``, a test's ``CliRunner``, an unknown
word) reads the command list, which imports every module first.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Sequence
from typing import Annotated, Any

import typer

#: The module (under melfa.cli) that registers each command; a test keeps it true.
COMMAND_MODULES: dict[str, str] = {
    "check": "lang_commands",
    "fmt": "lang_commands",
    **dict.fromkeys(
        [
            "upload",
            "run",
            "stop",
            "delete",
            "exec",
            "pose",
            "hand",
            "servo",
            "reset",
            "status",
            "jog",
        ],
        "robot_commands",
    ),
    "doctor": "doctor_commands",
    "sim": "sim_commands",
    "debug": "debug_commands",
    "grade": "grade_commands",
    "users": "users_commands",
    "serve": "serve_commands",
    "ros": "ros_commands",
    "desktop": "desktop_commands",
}
MODULES = tuple(dict.fromkeys(COMMAND_MODULES.values()))


class OnDemandTyper(typer.Typer):
    """A Typer whose command modules are imported when their commands are needed."""

    def __init__(self, **kwargs: Any) -> None:
        self._loading = False
        self._complete = False
        super().__init__(**kwargs)

    def load(self, modules: Sequence[str] = MODULES) -> None:
        """Import `modules` (each registers its commands on this app when imported)."""
        # Imported on demand rather than at the top, for start-up time (see the docstring).
        self._loading = True
        try:
            for name in modules:
                importlib.import_module(f"melfa.cli.{name}")
        finally:
            self._loading = False
        if tuple(modules) == MODULES:
            self._complete = True

    def _ensure_all(self) -> None:
        if not self._complete and not self._loading:
            self.load()

    # Typer reads these two lists to build the command line: every command must be there.
    @property
    def registered_commands(self) -> list[Any]:
        self._ensure_all()
        return self._commands

    @registered_commands.setter
    def registered_commands(self, value: list[Any]) -> None:
        self._commands = value

    @property
    def registered_groups(self) -> list[Any]:
        self._ensure_all()
        return self._groups

    @registered_groups.setter
    def registered_groups(self, value: list[Any]) -> None:
        self._groups = value

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        words = [a for a in sys.argv[1:] if not a.startswith("-")]
        module = COMMAND_MODULES.get(words[0]) if words else None
        if module is not None and not self._complete:
            self.load((module,))
            names = {c.name or c.callback.__name__ for c in self._commands if c.callback}
            names |= {g.name for g in self._groups}
            # The one command asked for is all this run needs, if its module registered it
            # (a command moved to another module falls back to loading them all).
            self._complete = words[0] in names
        return super().__call__(*args, **kwargs)


app = OnDemandTyper(
    name="melfa",
    help="Program and drive a Mitsubishi RV-6S (CR2B-574, MELFA BASIC IV).",
    no_args_is_help=True,
    add_completion=True,  # --install-completion / --show-completion (bash, zsh, fish)
    pretty_exceptions_enable=False,
    # -h as well as --help, on `melfa` and every command (subcommands inherit it).
    context_settings={"help_option_names": ["-h", "--help"]},
)


def _print_version(wanted: bool) -> None:
    if wanted:
        from importlib.metadata import version  # the installed package's (pyproject's)

        typer.echo(f"melfa {version('melfa')}")
        raise typer.Exit()


@app.callback()
def _root(
    version: Annotated[
        bool,
        typer.Option(
            "--version",
            "-V",
            help="Print melfa's version and exit.",
            callback=_print_version,
            is_eager=True,
        ),
    ] = False,
) -> None:
    """Program and drive a Mitsubishi RV-6S (CR2B-574, MELFA BASIC IV)."""
    # A callback keeps `melfa` a group of commands even when only one command module is
    # loaded (Typer runs a lone command as the whole program otherwise).
