"""Import and export of `.MB4` programs and `.POS` points files.

Workspaces hold programs in editor form (step numbers stripped, as `melfa fmt --strip`
does, keeping those that jumps name) and points in the project's `DEF POS` form. Files
exchanged with other tools are numbered (`number_lines`) and canonical (`format_points`).

Files from Windows tools arrive as UTF-8 or Windows-1252 with CRLF line ends; both are
read, and stored with LF. A wrong extension is refused with `WrongExtension`, a file that
cannot be converted without changing its meaning with `TransferError` (its diagnostics
carry line and column, like `melfa check`). Pure: no I/O, no clock.
"""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass

from melfa.lang.diagnostics import Diagnostic
from melfa.lang.encoding import decode_text
from melfa.lang.numbering import renumber, strip
from melfa.lang.points_read import parse_points
from melfa.lang.points_write import format_points
from melfa.store.errors import TransferError, WrongExtension

__all__ = [
    "ExportedFile",
    "FileKind",
    "decode_text",
    "file_kind",
    "points_from_file",
    "points_to_file",
    "program_from_file",
    "program_to_file",
]


class FileKind(enum.Enum):
    PROGRAM = ".MB4"
    POINTS = ".POS"


@dataclass(frozen=True, slots=True)
class ExportedFile:
    filename: str
    text: str


def _basename(filename: str) -> str:
    """Browsers may send a full path (old ones, with backslashes); keep the last part."""
    return re.split(r"[\\/]", filename)[-1]


def file_kind(filename: str) -> FileKind:
    """Which kind of file the name says; `WrongExtension` for anything else.

    >>> file_kind("C:\\\\lab\\\\pick.mb4"), file_kind("points.POS")
    (<FileKind.PROGRAM: '.MB4'>, <FileKind.POINTS: '.POS'>)
    """
    name = _basename(filename)
    for kind in FileKind:
        if name.upper().endswith(kind.value) and len(name) > len(kind.value):
            return kind
    raise WrongExtension(name or filename, "program (.MB4) or points (.POS)")


def _expect(filename: str, kind: FileKind) -> str:
    name = _basename(filename)
    if not (name.upper().endswith(kind.value) and len(name) > len(kind.value)):
        what = "program (.MB4)" if kind is FileKind.PROGRAM else "points (.POS)"
        raise WrongExtension(name or filename, what)
    return name


def program_from_file(filename: str, data: bytes | str) -> str:
    """A `.MB4` file's program in editor form (numbers stripped where nothing jumps to them)."""
    name = _expect(filename, FileKind.PROGRAM)
    result = strip(decode_text(data))
    if not result.ok:
        raise TransferError(
            name, "cannot remove the step numbers safely", _errors(result.diagnostics)
        )
    return result.text


def program_to_file(program: str, stem: str = "program") -> ExportedFile:
    """The workspace program numbered 10, 20, … (jumps rewritten) as a `.MB4` file."""
    result = renumber(program)
    filename = _safe_stem(stem) + FileKind.PROGRAM.value
    if not result.ok:
        raise TransferError(
            filename, "cannot number the program safely", _errors(result.diagnostics)
        )
    return ExportedFile(filename, result.text)


def points_from_file(filename: str, data: bytes | str) -> str:
    """A `.POS` file's text, checked; kept as written (comments too)."""
    name = _expect(filename, FileKind.POINTS)
    text = decode_text(data)
    parsed = parse_points(text)
    if parsed.has_errors:
        raise TransferError(name, "the points file has errors", _errors(parsed.diagnostics))
    return text


def points_to_file(points: str, stem: str = "points") -> ExportedFile:
    """The workspace points as a canonical `.POS` file (one `DEF` line each, 2 decimals)."""
    filename = _safe_stem(stem) + FileKind.POINTS.value
    parsed = parse_points(points)
    if parsed.has_errors:
        raise TransferError(filename, "the points have errors", _errors(parsed.diagnostics))
    return ExportedFile(filename, format_points(parsed.points))


def _errors(diagnostics: tuple[Diagnostic, ...]) -> tuple[Diagnostic, ...]:
    """The errors that made us refuse (infos and warnings are not the reason)."""
    return tuple(d for d in diagnostics if d.is_error)


def _safe_stem(stem: str) -> str:
    """A file name stem safe in a Content-Disposition header and on every file system."""
    safe = re.sub(r"[^A-Za-z0-9._-]+", "_", stem).strip("._")
    return safe or "workspace"
