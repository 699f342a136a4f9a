"""The Typer application object every command module registers on."""

import typer

app = typer.Typer(
    name="melfa",
    help="Program and drive a Mitsubishi RV-6S (CR2B-574, MELFA BASIC IV).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
