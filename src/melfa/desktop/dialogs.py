"""The one place the desktop client opens modal dialogs: message boxes and file choosers.

The window never calls `QMessageBox` or `QFileDialog` itself; it asks its `Dialogs`. The
application uses `QtDialogs`; tests pass their own recorder, so they can read exactly
what the user would have been told (and choose files) without a modal loop.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QFileDialog, QMessageBox, QWidget

from melfa.protocol.advice import FIX_LABELS, Fix

MAX_LISTED = 25
"""A dialog lists at most this many diagnostics; the check panel has them all."""


class NoticeKind(enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Notice:
    """What a message box says: a title, one sentence, optional lines (diagnostics), and the
    one action that fixes it (a button labelled as in `melfa.protocol.advice.FIX_LABELS`)."""

    kind: NoticeKind
    title: str
    text: str
    lines: tuple[str, ...] = ()
    fix: Fix | None = None

    @property
    def fix_label(self) -> str | None:
        return FIX_LABELS[self.fix] if self.fix is not None else None

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
    def show(
        self, notice: Notice, parent: QWidget | None, on_fix: Callable[[], object] | None = None
    ) -> None:
        """Show ``notice`` without blocking the window (STOP stays clickable); ``on_fix``
        runs when the user chooses the notice's fix."""
        ...

    def open_file(self, title: str, filters: str, parent: QWidget | None) -> Path | None: ...


class QtDialogs:
    """Real modal dialogs."""

    def __init__(self) -> None:
        self.folder = ""
        self.open_boxes: list[QMessageBox] = []
        """Notices on screen (kept referenced while they are shown)."""

    def show(
        self, notice: Notice, parent: QWidget | None, on_fix: Callable[[], object] | None = None
    ) -> None:
        icon = {
            NoticeKind.ERROR: QMessageBox.Icon.Critical,
            NoticeKind.WARNING: QMessageBox.Icon.Warning,
            NoticeKind.INFO: QMessageBox.Icon.Information,
        }[notice.kind]
        box = QMessageBox(icon, notice.title, notice.text, QMessageBox.StandardButton.Ok, parent)
        box.setWindowModality(Qt.WindowModality.NonModal)  # STOP stays clickable behind it
        if notice.lines:
            box.setInformativeText(notice.listing)
        if notice.fix_label and on_fix is not None:
            fix = box.addButton(notice.fix_label, QMessageBox.ButtonRole.AcceptRole)
            box.setDefaultButton(fix)
            fix.clicked.connect(lambda: on_fix())
        # Forgotten (and deleted) when closed, by the box's own signal: a box deleted on close
        # and asked later whether it is visible raised "Internal C++ object already deleted".
        box.finished.connect(lambda _result, closed=box: self._closed(closed))
        self.open_boxes.append(box)
        box.show()

    def _closed(self, box: QMessageBox) -> None:
        if box in self.open_boxes:
            self.open_boxes.remove(box)
        box.deleteLater()

    def open_file(self, title: str, filters: str, parent: QWidget | None) -> Path | None:
        name, _ = QFileDialog.getOpenFileName(parent, title, self.folder, filters)
        if not name:
            return None
        path = Path(name)
        self.folder = str(path.parent)
        return path


__all__ = ["MAX_LISTED", "Dialogs", "Notice", "NoticeKind", "QtDialogs"]
