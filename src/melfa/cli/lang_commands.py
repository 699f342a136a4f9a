"""`melfa check` and `melfa fmt` as Typer commands.

`melfa check` lives in `melfa.cli.checking` (no Typer, for start-up time); its command here
forwards to it. `melfa fmt` formats a program in place, in the encoding it was read with.
"""

from __future__ import annotations

import difflib
import os
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape

from melfa.cli.check_rich import print_lines, rich_console
from melfa.cli.checking import (
    ColorMode,
    FileKind,
    FileReport,
    UsageError,
    check_files,
    check_main,
    encode_as_read,
    read_source,
    report_lines,
    wants_color,
)
from melfa.cli.typer_app import app
from melfa.lang.format import FormatResult, LineNumbers, format_program
from melfa.lang.project import by_position

__all__ = ["FileKind", "UsageError", "check_files", "print_text", "read_source"]


def print_text(reports: Sequence[FileReport], console: Console) -> None:
    """The findings as `report_lines` lays them out; source excerpts only on a terminal."""
    print_lines(report_lines(reports, excerpts=console.is_terminal), console)


def _console(color: ColorMode, *, stderr: bool = False) -> Console:
    stream = sys.stderr if stderr else sys.stdout
    return rich_console(stream, terminal=wants_color(color, stream))  # NO_COLOR as check


def _fail(message: str, code: int = 2) -> typer.Exit:
    """One red line on stderr; the caller raises the returned `typer.Exit`."""
    _console(ColorMode.AUTO, stderr=True).print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(code)


# --- commands ----------------------------------------------------------------------------


@app.command(
    context_settings={"allow_extra_args": True, "ignore_unknown_options": True},
    add_help_option=False,
)
def check(ctx: typer.Context) -> None:
    """Check MELFA BASIC IV programs and points files, like a compiler would.

    Exit status: 0 no errors (warnings allowed), 1 errors found, 2 usage error.
    """
    # The options are `melfa.cli.checking`'s (argparse): `melfa check` usually runs there
    # directly, without Typer, for start-up time; this command forwards to it.
    code = check_main(ctx.args)
    if code:
        raise typer.Exit(code)


@app.command()
def fmt(
    file: Annotated[Path, typer.Argument(help="The program (.MB4) to format.", show_default=False)],
    number: Annotated[
        bool, typer.Option("--number", help="Number every line (10, 20, 30…), rewriting jumps.")
    ] = False,
    strip: Annotated[
        bool,
        typer.Option("--strip", help="Remove line numbers, keeping those that jumps still use."),
    ] = False,
    start: Annotated[int, typer.Option("--start", min=1, help="First number.")] = 10,
    step: Annotated[int, typer.Option("--step", min=1, help="Increment between lines.")] = 10,
    check_only: Annotated[
        bool,
        typer.Option("--check", help="Write nothing; exit 1 if the file would change."),
    ] = False,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Write here instead of in place ('-' for stdout)."),
    ] = None,
) -> None:
    """Upper-case keywords and, on request, number or strip line numbers.

    Only the case of the language's own words changes: names, strings and comments stay as
    written. A program with syntax errors is still formatted (line by line, nothing lost);
    numbering is refused, and nothing written, if a jump names a step that does not exist.
    """
    if number and strip:
        raise _fail("--number and --strip cannot be used together")
    try:
        source = read_source(file)
    except UsageError as err:
        raise _fail(str(err)) from None
    if source.kind is not FileKind.PROGRAM:
        raise _fail(f"{file}: melfa fmt formats programs (.MB4), not points files")
    if not source.is_text:
        raise _fail(f"{file}: {source.diagnostics[0].message}")
    mode = LineNumbers.NUMBER if number else LineNumbers.STRIP if strip else LineNumbers.KEEP
    result: FormatResult = format_program(source.text, mode, start=start, step=step)
    err_console = _console(ColorMode.AUTO, stderr=True)
    if result.diagnostics:
        report = FileReport(file, source, list(by_position(result.diagnostics)))
        print_text([report], err_console)
    if not result.ok:
        err_console.print(
            f"[bold red]error:[/] {escape(str(file))}: not formatted, nothing written"
        )
        raise typer.Exit(1)
    changed = result.text != source.text
    if check_only:
        if changed:
            diff = difflib.unified_diff(
                source.text.splitlines(keepends=True),
                result.text.splitlines(keepends=True),
                fromfile=str(file),
                tofile=f"{file} (formatted)",
            )
            sys.stdout.write("".join(line if line.endswith("\n") else line + "\n" for line in diff))
            err_console.print(f"would reformat {escape(str(file))}")
            raise typer.Exit(1)
        err_console.print(f"{escape(str(file))} is already formatted")
        return
    data = encode_as_read(source, result.text)
    if output is not None and str(output) == "-":
        sys.stdout.flush()
        sys.stdout.buffer.write(data)
        sys.stdout.buffer.flush()
        return
    target = output or file
    if target == file and not changed:
        err_console.print(f"{escape(str(file))} unchanged")
        return
    try:
        _write_atomically(target, data)
    except OSError as err:
        raise _fail(f"{target}: cannot write it ({err.strerror or err})") from None
    err_console.print(
        f"formatted {escape(str(file))}" + (f" -> {escape(str(target))}" if target != file else "")
    )


def _write_atomically(path: Path, data: bytes) -> None:
    """Write via a temporary file in the same folder, so a failure never leaves half a file."""
    if path.is_dir():
        raise IsADirectoryError(21, "is a directory")
    folder = path.parent
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
        if path.exists():
            mode = path.stat().st_mode & 0o7777
        else:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(tmp, mode)  # noqa: PTH101
        os.replace(tmp, path)  # noqa: PTH105
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
