"""`melfa check` itself: read files, check them (`melfa.lang.project`), print, exit code.

Kept free of Typer and Rich so that `melfa check` starts fast (editors and pre-commit hooks
run it on every save): `melfa.cli.main` calls `check_main` directly for ``melfa check …``,
and the Typer command of the same name only forwards to it, so the options are declared
once, here. Rich is imported only to colour a terminal's output (`melfa.cli.check_rich`).

The file handling that needs care lives here too (`melfa fmt` uses it):

* Files are read as bytes and decoded by `melfa.lang.encoding.decode_file`: UTF-16 with a
  BOM (Windows Notepad), UTF-8 (a BOM is dropped and written back), Windows-1252, then
  Latin-1, which never fails; the thesis's programs carry Catalan comments in Latin-1.
  Formatting writes the same encoding back.
* A file with NUL bytes is not a program: `check` reports it as an error diagnostic on that
  file (exit 1), `fmt` refuses it (exit 2).
* One reader for every command that takes a program (`read_text_file`: `upload`, `debug`,
  `sim --run`, and `check`/`fmt` through `read_source`): the same encodings, binary files
  refused, and the same extension rules: a program is a `.MB4`, a points file a `.POS`
  (a `.POS` or a `.txt` given as the program is refused with what to do).
* A points file is also checked against the robot: a point the RV-6S cannot reach gets a
  warning on its line (`melfa.kin.reach`), for the points a program may move to.
* Usage mistakes (no such file, a directory, an unknown extension, bad options) are one
  line on stderr and exit 2; errors in a program exit 1; warnings alone exit 0.
"""

from __future__ import annotations

import argparse
import enum
import json
import os
import sys
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TextIO

from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.encoding import decode_file
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
    """Read and decode one file; raise `UsageError` when it cannot be read at all, or when
    its extension says it is not the `kind` of file asked for."""
    found = _kind_of(path)
    if kind is not None and found is not kind:
        want = PROGRAM_SUFFIX if kind is FileKind.PROGRAM else POINTS_SUFFIX
        how = " (give it with --points)" if found is FileKind.POINTS else ""
        raise UsageError(
            f"{path}: this is a {found.value} file{how}; a {kind.value} file is a {want} file"
        )
    kind = found
    if path.is_dir():
        raise UsageError(f"{path}: is a directory, not a file")
    if not path.exists():
        raise UsageError(f"{path}: no such file")
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise UsageError(f"{path}: cannot read it ({err.strerror or err})") from err
    source = SourceFile(path, kind, raw)
    decoded = decode_file(raw)
    source.text, source.encoding, source.bom = decoded.text, decoded.encoding, decoded.bom
    if decoded.binary_at is not None:
        line, column = decoded.binary_at
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


def read_text_file(path: Path, kind: FileKind) -> SourceFile:
    """The one reader of a program or points file for the commands that run or send it:
    `read_source`'s encodings and extension rules, and a binary file refused (UsageError)."""
    source = read_source(path, kind)
    binary = next((d for d in source.diagnostics if d.rule == "file-binary"), None)
    if binary is not None:
        raise UsageError(f"{path}: {binary.message}")
    return source


def encode_as_read(source: SourceFile, text: str) -> bytes:
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

Segment = tuple[str, str | None]
"""A piece of an output line and its Rich style (None: plain)."""

STYLE = {Severity.ERROR: "bold red", Severity.WARNING: "bold yellow", Severity.INFO: "bold cyan"}


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


def report_lines(reports: Sequence[FileReport], excerpts: bool) -> Iterator[list[Segment]]:
    """Compiler style: ``file:line:col: error: message [CODE]``, a hint, and (`excerpts`,
    on a terminal) the source line with carets; then the summary."""
    for report in reports:
        lines = report.source.text.splitlines() if report.source.is_text else []
        for d in report.diagnostics:
            code = f" [{d.code}]" if d.code else ""
            yield [
                (f"{report.path}:{d.line}:{d.column}: ", "bold"),
                (f"{d.severity.value}:", STYLE[d.severity]),
                (f" {d.message}{code}", None),
            ]
            if d.suggestion:
                yield [("  = ", None), ("help", "bold green"), (f": {d.suggestion}", None)]
            if excerpts and 0 < d.line <= len(lines):
                shown, carets = _source_excerpt(lines[d.line - 1], d)
                gutter = f"{d.line:>5} | "
                yield [(gutter, "blue"), (shown, None)]
                yield [(" " * (len(gutter) - 2) + "| ", "blue"), (carets, STYLE[d.severity])]
    counts = _severity_counts(reports)
    style = (
        "bold red"
        if counts[Severity.ERROR]
        else "bold yellow"
        if counts[Severity.WARNING]
        else "bold green"
    )
    yield [(summary_line(reports), style)]


def wants_color(color: ColorMode, stream: TextIO) -> bool:
    """``--color always``; or ``auto`` on a terminal, unless ``NO_COLOR`` is set and not
    empty (https://no-color.org)."""
    if color is ColorMode.AUTO:
        return stream.isatty() and not os.environ.get("NO_COLOR")
    return color is ColorMode.ALWAYS


def print_reports(reports: Sequence[FileReport], color: ColorMode, stream: TextIO) -> None:
    """Coloured (Rich, loaded then) or plain text; source excerpts on a terminal either way."""
    if wants_color(color, stream):
        # Imported only for a terminal, for start-up time: Rich costs more than checking.
        from melfa.cli.check_rich import print_lines, rich_console

        print_lines(report_lines(reports, excerpts=True), rich_console(stream, terminal=True))
        return
    for line in report_lines(reports, excerpts=color is ColorMode.AUTO and stream.isatty()):
        stream.write("".join(text for text, _ in line) + "\n")


# --- the command -------------------------------------------------------------------------


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        """One line on stderr and exit 2, as every melfa command reports a usage mistake."""
        sys.stderr.write(f"error: {message} (see melfa check --help)\n")
        raise SystemExit(2)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="melfa check",
        description="Check MELFA BASIC IV programs and points files, like a compiler would. "
        "Exit status: 0 no errors (warnings allowed), 1 errors found, 2 usage error.",
    )
    parser.add_argument(
        "files",
        nargs="+",
        type=Path,
        metavar="FILES",
        help="Programs (.MB4) and points files (.POS) to check; case of the extension "
        "does not matter.",
    )
    parser.add_argument(
        "--points",
        "-p",
        type=Path,
        help="Points file (.POS) defining the positions the programs use. Any .POS file "
        "among FILES supplies names too.",
    )
    parser.add_argument(
        "--format",
        "-f",
        dest="output_format",
        type=OutputFormat,
        choices=list(OutputFormat),
        default=OutputFormat.TEXT,
        help="text for people, json for tools.",
    )
    parser.add_argument(
        "--color",
        type=ColorMode,
        choices=list(ColorMode),
        default=ColorMode.AUTO,
        help="Colours and source excerpts: auto (on a terminal), always or never.",
    )
    return parser


LONG_WORK_BYTES = 256 * 1024
"""Checking this much text takes seconds: a terminal is told what is being checked."""


@dataclass
class _Feedback:
    stream: TextIO
    shown: str = ""

    def done(self) -> None:
        """Clear the line said while working (the findings follow on a clean line)."""
        if self.shown:
            self.stream.write("\r" + " " * len(self.shown) + "\r")
            self.stream.flush()


def _announce_long_work(sources: Sequence[SourceFile], stream: TextIO) -> _Feedback:
    """On a terminal, a line saying what is checked when that takes long (a 5 MB file: many
    seconds); nothing in a pipe or for small files."""
    size = sum(len(source.raw) for source in sources)
    if size < LONG_WORK_BYTES or not stream.isatty():
        return _Feedback(stream)
    names = sources[0].path.name if len(sources) == 1 else f"{len(sources)} files"
    text = f"checking {names} ({size / 1_000_000:.1f} MB)…"
    stream.write(text)
    stream.flush()
    return _Feedback(stream, text)


def check_main(argv: Sequence[str]) -> int:
    """``melfa check ARGV``: print the findings and return the exit status (0, 1 or 2)."""
    try:
        args = _parser().parse_args(list(argv))
    except SystemExit as done:  # --help (0) or a usage mistake (2, already reported)
        return int(done.code or 0)
    sources: list[SourceFile] = []
    seen: set[Path] = set()
    try:
        for path in args.files:
            sources.append(read_source(path))
            seen.add(path.resolve())
        points = args.points
        if points is not None:
            if points.suffix.upper() != POINTS_SUFFIX:
                raise UsageError(f"{points}: --points takes a .POS points file")
            if points.resolve() not in seen:
                sources.append(read_source(points, FileKind.POINTS))
    except UsageError as err:
        sys.stderr.write(f"error: {err}\n")
        return 2
    feedback = _announce_long_work(sources, sys.stderr)
    reports = check_files(sources)
    feedback.done()
    try:
        if args.output_format is OutputFormat.JSON:
            sys.stdout.write(
                json.dumps([r.to_json() for r in reports], indent=2, ensure_ascii=False) + "\n"
            )
        else:
            print_reports(reports, args.color, sys.stdout)
        sys.stdout.flush()
    except BrokenPipeError:  # `melfa check … | head`: the reader has all it wanted
        sys.stdout = Path(os.devnull).open("w")  # noqa: SIM115  (no flush error at exit)
    return 1 if _severity_counts(reports)[Severity.ERROR] else 0
