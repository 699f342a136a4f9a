"""The one place the desktop client opens modal dialogs: message boxes and file choosers.

The window never calls `QMessageBox` or `QFileDialog` itself; it asks its `Dialogs`. The
application uses `QtDialogs`; tests pass their own recorder, so they can read exactly
what the user would have been told (and choose files) without a modal loop.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from PySide6.QtWidgets import QFileDialog, QMessageBox, QWidget

MAX_LISTED = 25
"""A dialog lists at most this many diagnostics; the check panel has them all."""


class NoticeKind(enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Notice:
    """What a message box says: a title, one sentence, and optional lines (diagnostics)."""

    kind: NoticeKind
    title: str
    text: str
    lines: tuple[str, ...] = ()

    @property
    def listing(self) -> str:
        """
        >>> Notice(NoticeKind.ERROR, "t", "x", tuple(f"{n}:1 bad" for n in range(1, 28))).listing
        ... # doctest: +ELLIPSIS
        '1:1 bad\\n2:1 bad\\n...25:1 bad\\n… and 2 more'
        """
        shown = list(self.lines[:MAX_LISTED])
        if len(self.lines) > MAX_LISTED:
            shown.append(f"… and {len(self.lines) - MAX_LISTED} more")
        return "\n".join(shown)


class Dialogs(Protocol):
    def show(self, notice: Notice, parent: QWidget | None) -> None: ...

    def open_file(self, title: str, filters: str, parent: QWidget | None) -> Path | None: ...


class QtDialogs:
    """Real modal dialogs."""

    def __init__(self) -> None:
        self.folder = ""

    def show(self, notice: Notice, parent: QWidget | None) -> None:
        icon = {
            NoticeKind.ERROR: QMessageBox.Icon.Critical,
            NoticeKind.WARNING: QMessageBox.Icon.Warning,
            NoticeKind.INFO: QMessageBox.Icon.Information,
        }[notice.kind]
        box = QMessageBox(icon, notice.title, notice.text, QMessageBox.StandardButton.Ok, parent)
        if notice.lines:
            box.setInformativeText(notice.listing)
        box.exec()

    def open_file(self, title: str, filters: str, parent: QWidget | None) -> Path | None:
        name, _ = QFileDialog.getOpenFileName(parent, title, self.folder, filters)
        if not name:
            return None
        path = Path(name)
        self.folder = str(path.parent)
        return path


__all__ = ["MAX_LISTED", "Dialogs", "Notice", "NoticeKind", "QtDialogs"]
