"""`melfa desktop`: sign in, then the main window until it is closed."""

from __future__ import annotations

import contextlib
import signal
import sys
from collections.abc import Callable, Iterator
from types import FrameType

from PySide6.QtCore import QTimer
from PySide6.QtGui import QFont
from PySide6.QtWidgets import QApplication, QDialog

from melfa.desktop.dialogs import QtDialogs
from melfa.desktop.login import LoginDialog
from melfa.desktop.presenter import Presenter
from melfa.desktop.style import STYLE
from melfa.desktop.window import MainWindow

BASE_POINT_SIZE = 10.5
"""Readable on a lab PC's 1080p screen from a step back."""

SIGNAL_CHECK_MS = 200
"""How often Qt's event loop lets Python run: Python handles a signal (Ctrl-C) only while
it runs Python code, and Qt's loop is not Python, so Ctrl-C waited for the next click."""


def application() -> QApplication:
    """The one QApplication (created once), with the Fusion style and a readable font."""
    existing = QApplication.instance()
    if isinstance(existing, QApplication):
        return existing
    app = QApplication(sys.argv[:1])
    app.setApplicationName("melfa desktop")
    app.setStyle("Fusion")
    font = QFont(app.font())
    font.setPointSizeF(BASE_POINT_SIZE)
    app.setFont(font)
    return app


class _CtrlC:
    """Ctrl-C (SIGINT) while the client runs: ``end`` closes what is on screen (the sign-in
    dialog, or every event loop of the window: the window's and a notice's over it), so
    the client ends as cleanly as when closed. Before, `melfa desktop` in a terminal
    ignored Ctrl-C until something happened on the screen."""

    def __init__(self) -> None:
        self.came = False
        self.end: Callable[[], object] = lambda: None

    def __call__(self, signum: int, frame: FrameType | None) -> None:
        self.came = True
        self.end()


@contextlib.contextmanager
def _handled(ctrl_c: _CtrlC) -> Iterator[None]:
    """``ctrl_c`` handles SIGINT meanwhile, and Qt's loop lets Python run often enough."""
    previous = signal.signal(signal.SIGINT, ctrl_c)
    timer = QTimer()
    timer.timeout.connect(lambda: None)
    timer.start(SIGNAL_CHECK_MS)
    try:
        yield
    finally:
        timer.stop()
        signal.signal(signal.SIGINT, previous)


def main(server: str, username: str = "") -> int:
    """Run the client; the exit code of the Qt event loop (0 when closed normally). Ctrl-C
    closes it as cleanly, then raises `KeyboardInterrupt` (the command line's status 130)."""
    app = application()
    ctrl_c = _CtrlC()
    with _handled(ctrl_c):
        code = _run(app, ctrl_c, server, username)
    if ctrl_c.came:
        raise KeyboardInterrupt
    return code


def _run(app: QApplication, ctrl_c: _CtrlC, server: str, username: str) -> int:
    login = LoginDialog(server, username)
    login.setStyleSheet(STYLE)
    ctrl_c.end = login.reject  # not app.exit: with no app.exec running, it would stay set
    if login.exec() != QDialog.DialogCode.Accepted or login.client is None or ctrl_c.came:
        return 0
    presenter = Presenter(login.client)
    window = MainWindow(presenter, QtDialogs(), on_closed=app.quit)
    window.show()
    presenter.start()
    ctrl_c.end = app.exit
    try:
        return 0 if ctrl_c.came else app.exec()
    finally:
        presenter.shutdown()


__all__ = ["application", "main"]
