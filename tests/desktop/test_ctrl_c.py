"""Ctrl-C on `melfa desktop` in a terminal: the sign-in dialog or the window closes and the
command ends (status 130, as every command's Ctrl-C). Qt's event loop is not Python, and
Python runs a signal's handler only while it runs Python code, so before, Ctrl-C did
nothing until something happened on the screen. The real entry point, offscreen, and a
real SIGINT sent to this process."""

from __future__ import annotations

import os
import signal

import pytest

os.environ["QT_QPA_PLATFORM"] = "offscreen"  # before Qt starts: no display needed
pytest.importorskip("PySide6.QtWidgets", reason="the desktop extra (PySide6) is not installed")

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QApplication

from melfa.desktop.app import application, main
from melfa.desktop.login import LoginDialog
from melfa.desktop.window import MainWindow
from tests.desktop.conftest import Server

GUARD_MS = 60_000
"""Closes what is still open after this long, so a Ctrl-C that is ignored fails the test
rather than hanging it."""


def _ctrl_c_once(shown: type, then: list[str]) -> None:
    """Once a ``shown`` widget is on screen, SIGINT to this process (as a terminal's
    Ctrl-C); a guard closes every window if that does not end the client."""

    def guard() -> None:
        then.append("still open")
        for widget in QApplication.topLevelWidgets():
            widget.close()

    def when_shown() -> None:
        visible = [w for w in QApplication.topLevelWidgets() if isinstance(w, shown)]
        if not any(w.isVisible() for w in visible):
            QTimer.singleShot(20, when_shown)
            return
        windows = [w for w in visible if isinstance(w, MainWindow)]
        if shown is MainWindow and not any(w.presenter.live.state for w in windows):
            QTimer.singleShot(20, when_shown)
            return
        QTimer.singleShot(GUARD_MS, guard)
        then.append("sent")
        os.kill(os.getpid(), signal.SIGINT)

    QTimer.singleShot(0, when_shown)


def test_ctrl_c_at_the_sign_in_dialog_ends_the_client() -> None:
    application()
    then: list[str] = []
    _ctrl_c_once(LoginDialog, then)
    with pytest.raises(KeyboardInterrupt):
        main("http://127.0.0.1:9", "admin")  # nothing listens: the dialog just waits
    assert then == ["sent"]
    assert not [
        w for w in QApplication.topLevelWidgets() if isinstance(w, LoginDialog) and w.isVisible()
    ]


def test_ctrl_c_at_the_window_ends_the_client(server: Server) -> None:
    application()
    then: list[str] = []

    def sign_in_when_asked() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, LoginDialog):
            QTimer.singleShot(20, sign_in_when_asked)
            return
        dialog.password_edit.setText(server.password)
        dialog.sign_in_button.click()

    QTimer.singleShot(0, sign_in_when_asked)
    _ctrl_c_once(MainWindow, then)
    with pytest.raises(KeyboardInterrupt):
        main(server.url, "admin")
    assert then == ["sent"]
