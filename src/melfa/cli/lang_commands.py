"""`melfa check` and `melfa fmt`: the MELFA BASIC IV checker and formatter on files.

Thin: read files, call `melfa.lang`, print. The file handling that needs care lives here:

* Files are read as bytes and decoded as UTF-8 (a BOM is dropped and written back), then
  Latin-1, which never fails; the thesis's programs carry Catalan comments in Latin-1.
  UTF-16 with a BOM (Windows Notepad) is read too. Formatting writes the same encoding back.
* A file with NUL bytes is not a program: `check` reports it as an error diagnostic on that
  file (exit 1), `fmt` refuses it (exit 2).
* A points file is also checked against the robot: a point the RV-6S cannot reach gets a
  warning on its line (`melfa.kin.reach`).
* Usage mistakes (no such file, a directory, an unknown extension, bad options) are one red
  line on stderr and exit 2; errors in a program exit 1; warnings alone exit 0.
"""

from __future__ import annotations

import codecs
import difflib
import enum
import json
import os
import sys
import tempfile
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.markup import escape
from rich.text import Text

from melfa.cli.app import app
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.format import FormatResult, LineNumbers, format_program
from melfa.lang.points import PointDef
from melfa.lang.project import by_position, check_project

PROGRAM_SUFFIX = ".MB4"
POINTS_SUFFIX = ".POS"
_SOURCE_WINDOW = 120
"""Longest slice of a source line shown under a diagnostic (very long lines are cut)."""


class OutputFormat(enum.StrEnum):
    TEXT = "text"
    JSON = "json"


class ColorMode(enum.StrEnum):
    AUTO = "auto"
    ALWAYS = "always"
    NEVER = "never"


class FileKind(enum.Enum):
    PROGRAM = "program"
    POINTS = "points"


class UsageError(Exception):
    """The user asked for something we cannot do (exit 2)."""


@dataclass(slots=True)
class SourceFile:
    """One file as read: its text (when it is text) and what reading it found."""

    path: Path
    kind: FileKind
    raw: bytes
    text: str = ""
    encoding: str = "utf-8"
    bom: bytes = b""
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def is_text(self) -> bool:
        return not any(d.rule == "file-binary" for d in self.diagnostics)


# --- reading -----------------------------------------------------------------------------


def _kind_of(path: Path) -> FileKind:
    suffix = path.suffix.upper()
    if suffix == PROGRAM_SUFFIX:
        return FileKind.PROGRAM
    if suffix == POINTS_SUFFIX:
        return FileKind.POINTS
    shown = path.suffix or "no extension"
    raise UsageError(
        f"{path}: unknown file type ({shown}); melfa reads .MB4 programs and .POS points files"
    )


def read_source(path: Path, kind: FileKind | None = None) -> SourceFile:
    """Read and decode one file; raise `UsageError` when it cannot be read at all."""
    kind = kind or _kind_of(path)
    if path.is_dir():
        raise UsageError(f"{path}: is a directory, not a file")
    if not path.exists():
        raise UsageError(f"{path}: no such file")
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise UsageError(f"{path}: cannot read it ({err.strerror or err})") from err
    source = SourceFile(path, kind, raw)
    for bom, encoding in ((codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be")):
        if raw.startswith(bom):
            try:
                source.text = raw[len(bom) :].decode(encoding)
                source.encoding, source.bom = encoding, bom
                break
            except UnicodeDecodeError:
                pass
    else:
        nul = raw.find(b"\x00")
        if nul >= 0:
            before = raw[:nul].decode("latin-1")
            line = before.count("\n") + 1
            column = nul - (before.rfind("\n") + 1) + 1
            source.diagnostics.append(
                Diagnostic(
                    line,
                    column,
                    line,
                    column + 1,
                    Severity.ERROR,
                    f"This is not a text file (a NUL byte at line {line}, column {column}); "
                    "programs and points files are plain text",
                    "file-binary",
                    suggestion="Read the program from the controller as text, "
                    "or save it from the editor as plain text.",
                )
            )
            return source
        if raw.startswith(codecs.BOM_UTF8):
            source.bom = codecs.BOM_UTF8
            raw = raw[len(codecs.BOM_UTF8) :]
        try:
            source.text = raw.decode("utf-8")
        except UnicodeDecodeError:
            source.text, source.encoding = raw.decode("latin-1"), "latin-1"
    return source


def _encode(source: SourceFile, text: str) -> bytes:
    """Text back to bytes in the encoding it was read with (Latin-1 stays Latin-1)."""
    try:
        return source.bom + text.encode(source.encoding)
    except UnicodeEncodeError:
        return source.bom + text.encode("utf-8")


# --- checking ----------------------------------------------------------------------------


@dataclass(slots=True)
class FileReport:
    path: Path
    source: SourceFile
    diagnostics: list[Diagnostic]

    def to_json(self) -> dict[str, object]:
        return {"file": str(self.path), "diagnostics": [d.to_json() for d in self.diagnostics]}


def _reach(points: Sequence[PointDef], text: str) -> list[Diagnostic]:
    """Warnings for points the RV-6S cannot take (`melfa.kin.reach`)."""
    # Imported here, only when there are points to judge, for start-up time: the robot
    # model loads numpy, which costs more than the whole of checking a small program.
    from melfa.kin.reach import reach_diagnostics

    return reach_diagnostics(points, text)


def check_files(files: Sequence[SourceFile]) -> list[FileReport]:
    """Check programs against the names of every points file given; points files on their
    own, including whether the RV-6S can reach each point a program may move to (warnings).
    The checking is `melfa.lang.project.check_project`, the same as the web API's."""
    points = [i for i, s in enumerate(files) if s.kind is FileKind.POINTS and s.is_text]
    programs = [i for i, s in enumerate(files) if s.kind is FileKind.PROGRAM and s.is_text]
    report = check_project(
        [files[i].text for i in programs], [files[i].text for i in points], _reach
    )
    found: dict[int, tuple[Diagnostic, ...]] = dict(zip(points, report.points, strict=True))
    found.update(zip(programs, report.programs, strict=True))
    return [
        FileReport(
            source.path,
            source,
            list(by_position([*source.diagnostics, *found.get(i, ())])),
        )
        for i, source in enumerate(files)
    ]


# --- printing ----------------------------------------------------------------------------

_STYLE = {Severity.ERROR: "bold red", Severity.WARNING: "bold yellow", Severity.INFO: "bold cyan"}


def _console(color: ColorMode, *, stderr: bool = False) -> Console:
    stream = sys.stderr if stderr else sys.stdout
    terminal = color is ColorMode.ALWAYS or (color is ColorMode.AUTO and stream.isatty())
    return Console(
        file=stream,
        force_terminal=terminal,
        no_color=not terminal,
        highlight=False,
        soft_wrap=True,
        emoji=False,
    )


def _source_excerpt(line_text: str, d: Diagnostic) -> tuple[str, str]:
    """The source line (cut around the column when very long) and its caret underline."""
    start = d.column - 1
    end = d.end_column - 1 if d.end_line == d.line else len(line_text)
    end = max(min(end, len(line_text)), start + 1)
    offset = 0
    shown = line_text
    if len(line_text) > _SOURCE_WINDOW:
        offset = max(0, min(start - 20, len(line_text) - _SOURCE_WINDOW))
        shown = line_text[offset : offset + _SOURCE_WINDOW]
        end = min(end, offset + _SOURCE_WINDOW)
        if offset:
            shown = "…" + shown
            offset -= 1
    # Keep tabs in the padding so the caret lines up however the terminal sets tab stops.
    pad = "".join("\t" if c == "\t" else " " for c in shown[: start - offset])
    return shown, pad + "^" * max(1, end - start)


def _severity_counts(reports: Iterable[FileReport]) -> dict[Severity, int]:
    counts = dict.fromkeys(Severity, 0)
    for report in reports:
        for d in report.diagnostics:
            counts[d.severity] += 1
    return counts


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def summary_line(reports: Sequence[FileReport]) -> str:
    """``2 errors, 1 warning in 1 file`` (info messages are counted only when present)."""
    counts = _severity_counts(reports)
    parts = [_plural(counts[Severity.ERROR], "error"), _plural(counts[Severity.WARNING], "warning")]
    if counts[Severity.INFO]:
        parts.append(f"{counts[Severity.INFO]} info")
    return f"{', '.join(parts)} in {_plural(len(reports), 'file')}"


def print_text(reports: Sequence[FileReport], console: Console) -> None:
    """Compiler style: ``file:line:col: error: message [CODE]``, a hint, the source line."""
    rich_terminal = console.is_terminal
    for report in reports:
        lines = report.source.text.splitlines() if report.source.is_text else []
        for d in report.diagnostics:
            code = f" [{d.code}]" if d.code else ""
            head = Text()
            head.append(f"{report.path}:{d.line}:{d.column}: ", style="bold")
            head.append(f"{d.severity.value}:", style=_STYLE[d.severity])
            head.append(f" {d.message}{code}")
            console.print(head)
            if d.suggestion:
                console.print(Text.assemble("  = ", ("help", "bold green"), f": {d.suggestion}"))
            if rich_terminal and 0 < d.line <= len(lines):
                shown, carets = _source_excerpt(lines[d.line - 1], d)
                gutter = f"{d.line:>5} | "
                console.print(Text.assemble((gutter, "blue"), shown))
                console.print(
                    Text.assemble(
                        (" " * (len(gutter) - 2) + "| ", "blue"), (carets, _STYLE[d.severity])
                    )
                )
    counts = _severity_counts(reports)
    style = (
        "bold red"
        if counts[Severity.ERROR]
        else "bold yellow"
        if counts[Severity.WARNING]
        else "bold green"
    )
    console.print(Text(summary_line(reports), style=style))


def _fail(message: str, code: int = 2) -> typer.Exit:
    """One red line on stderr; the caller raises the returned `typer.Exit`."""
    _console(ColorMode.AUTO, stderr=True).print(f"[bold red]error:[/] {escape(message)}")
    return typer.Exit(code)


# --- commands ----------------------------------------------------------------------------


@app.command()
def check(
    files: Annotated[
        list[Path],
        typer.Argument(
            help="Programs (.MB4) and points files (.POS) to check; case of the extension "
            "does not matter.",
            show_default=False,
        ),
    ],
    points: Annotated[
        Path | None,
        typer.Option(
            "--points",
            "-p",
            help="Points file (.POS) defining the positions the programs use. Any .POS file "
            "among FILES supplies names too.",
        ),
    ] = None,
    output_format: Annotated[
        OutputFormat, typer.Option("--format", "-f", help="text for people, json for tools.")
    ] = OutputFormat.TEXT,
    color: Annotated[
        ColorMode,
        typer.Option(
            "--color",
            help="Colours and source excerpts: auto (on a terminal), always or never.",
        ),
    ] = ColorMode.AUTO,
) -> None:
    """Check MELFA BASIC IV programs and points files, like a compiler would.

    Exit status: 0 no errors (warnings allowed), 1 errors found, 2 usage error.
    """
    sources: list[SourceFile] = []
    seen: set[Path] = set()
    try:
        for path in files:
            sources.append(read_source(path))
            seen.add(path.resolve())
        if points is not None:
            if points.suffix.upper() != POINTS_SUFFIX:
                raise UsageError(f"{points}: --points takes a .POS points file")
            if points.resolve() not in seen:
                sources.append(read_source(points, FileKind.POINTS))
    except UsageError as err:
        raise _fail(str(err)) from None
    reports = check_files(sources)
    if output_format is OutputFormat.JSON:
        typer.echo(json.dumps([r.to_json() for r in reports], indent=2, ensure_ascii=False))
    else:
        print_text(reports, _console(color))
    if _severity_counts(reports)[Severity.ERROR]:
        raise typer.Exit(1)


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
    data = _encode(source, result.text)
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
