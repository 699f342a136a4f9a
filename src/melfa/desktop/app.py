"""`melfa desktop`: sign in, then the main window until it is closed."""

from __future__ import annotations

import sys

from PySide6.QtGui import QFont
from PySide6.QtWidgets import QApplication, QDialog

from melfa.desktop.dialogs import QtDialogs
from melfa.desktop.login import LoginDialog
from melfa.desktop.presenter import Presenter
from melfa.desktop.style import STYLE
from melfa.desktop.window import MainWindow

BASE_POINT_SIZE = 10.5
"""Readable on a lab PC's 1080p screen from a step back."""


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


def main(server: str, username: str = "") -> int:
    """Run the client; the exit code of the Qt event loop (0 when closed normally)."""
    app = application()
    login = LoginDialog(server, username)
    login.setStyleSheet(STYLE)
    if login.exec() != QDialog.DialogCode.Accepted or login.client is None:
        return 0
    presenter = Presenter(login.client)
    window = MainWindow(presenter, QtDialogs(), on_closed=app.quit)
    window.show()
    presenter.start()
    try:
        return app.exec()
    finally:
        presenter.shutdown()


__all__ = ["application", "main"]
