"""Which files the client accepts, and how it reads them. Pure, no Qt.

The rule mirrors the server's import rule (`wrong-extension` in docs/api.md): a program is
a `.MB4` file and a points file is a `.POS` file, in any letter case, as the thesis's RQt
client required (requirements 3.2.3 and 3.2.4). It is checked here, before anything is
sent, because `/api/robot/project` takes texts, not files.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from pathlib import Path

from melfa.lang.encoding import decode_text

MAX_FILE_BYTES = 2 * 1024 * 1024
"""The server refuses bigger imports (413 `too-large`); refuse them before reading."""


class FileKind(enum.Enum):
    PROGRAM = ".MB4"
    POINTS = ".POS"

    @property
    def label(self) -> str:
        return "program" if self is FileKind.PROGRAM else "points file"


class FileRefused(Exception):
    """The user chose a file the client cannot send (the user's mistake, not the server's)."""

    def __init__(self, path: Path, kind: FileKind, reason: str) -> None:
        super().__init__(f"{path.name}: {reason}")
        self.path = path
        self.kind = kind
        self.reason = reason


@dataclass(frozen=True)
class ChosenFile:
    """A program or points text and where it came from: a file on this computer, or a
    workspace on the server (``workspace``, its name; ``path`` is then its export name)."""

    path: Path
    kind: FileKind
    text: str
    workspace: str | None = None
    workspace_id: int | None = None

    @property
    def name(self) -> str:
        """What the window calls it: the file's name, or the workspace's.

        >>> ChosenFile(Path("/tmp/pick.MB4"), FileKind.PROGRAM, "").name
        'pick.MB4'
        >>> ChosenFile(Path("Lab 1.MB4"), FileKind.PROGRAM, "", "Lab 1", 7).name
        'Lab 1 (workspace)'
        """
        return f"{self.workspace} (workspace)" if self.workspace is not None else self.path.name


def has_extension(path: str | Path, kind: FileKind) -> bool:
    """True when the name ends with the kind's extension (any case) after a real stem.

    >>> has_extension("pick.MB4", FileKind.PROGRAM), has_extension("pick.mb4", FileKind.PROGRAM)
    (True, True)
    >>> has_extension("pick.txt", FileKind.PROGRAM), has_extension(".POS", FileKind.POINTS)
    (False, False)
    """
    name = Path(path).name
    return name.upper().endswith(kind.value) and len(name) > len(kind.value)


def check_extension(path: Path, kind: FileKind) -> None:
    """`FileRefused` with a message naming the expected extension."""
    if not has_extension(path, kind):
        suffix = path.suffix or "no extension"
        raise FileRefused(
            path,
            kind,
            f"wrong extension ({suffix}): choose a {kind.value} {kind.label}",
        )


def from_workspace(
    workspace_id: int, name: str, program: str, points: str
) -> tuple[ChosenFile, ChosenFile | None]:
    """A server workspace's texts as chosen program and points (no points: None).

    >>> p, q = from_workspace(7, "Lab 1", "MOV P1", "")
    >>> p.name, p.path.name, q
    ('Lab 1 (workspace)', 'Lab 1.MB4', None)
    """
    chosen = ChosenFile(Path(f"{name}.MB4"), FileKind.PROGRAM, program, name, workspace_id)
    if not points.strip():
        return chosen, None
    return chosen, ChosenFile(Path(f"{name}.POS"), FileKind.POINTS, points, name, workspace_id)


def read_file(path: Path, kind: FileKind) -> ChosenFile:
    """The file's text, or `FileRefused` (wrong extension, missing, too big, binary)."""
    check_extension(path, kind)
    try:
        size = path.stat().st_size
        if size > MAX_FILE_BYTES:
            raise FileRefused(path, kind, f"too large ({size} bytes; at most 2 MiB)")
        data = path.read_bytes()
    except FileNotFoundError:
        raise FileRefused(path, kind, "no such file") from None
    except IsADirectoryError:
        raise FileRefused(path, kind, "is a folder, not a file") from None
    except OSError as exc:
        raise FileRefused(path, kind, f"cannot be read ({exc.strerror or exc})") from None
    if b"\x00" in data:
        raise FileRefused(path, kind, "is not a text file")
    return ChosenFile(path, kind, decode_text(data))


__all__ = [
    "MAX_FILE_BYTES",
    "ChosenFile",
    "FileKind",
    "FileRefused",
    "check_extension",
    "from_workspace",
    "has_extension",
    "read_file",
]
