"""The sign-in dialog: server, username and password, with the server's refusal shown
inside the dialog (wrong password, too many attempts, no server), so the user can retry."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QGuiApplication
from PySide6.QtWidgets import (
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QLabel,
    QLineEdit,
    QVBoxLayout,
    QWidget,
)

from melfa.desktop.api import ApiClient, ApiError, ServerUnreachable, SignedIn


class LoginDialog(QDialog):
    """Signs in with `POST /api/session`; `client` is the signed-in client after accept."""

    def __init__(self, server: str, username: str = "", parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Sign in — melfa")
        self.setMinimumWidth(420)
        self.client: ApiClient | None = None
        self.user: SignedIn | None = None

        heading = QLabel("Sign in to the melfa server")
        heading.setObjectName("heading")
        note = QLabel("Use the same account as the web IDE.")
        note.setObjectName("muted")

        self.server_edit = QLineEdit(server)
        self.username_edit = QLineEdit(username)
        self.password_edit = QLineEdit()
        self.password_edit.setEchoMode(QLineEdit.EchoMode.Password)
        for edit, label in (
            (self.server_edit, "Server address"),
            (self.username_edit, "Username"),
            (self.password_edit, "Password"),
        ):
            edit.setAccessibleName(label)
        form = QFormLayout()
        form.addRow("&Server:", self.server_edit)
        form.addRow("&Username:", self.username_edit)
        form.addRow("&Password:", self.password_edit)

        self.error_label = QLabel("")
        self.error_label.setObjectName("error")
        self.error_label.setWordWrap(True)
        self.error_label.setVisible(False)

        self.buttons = QDialogButtonBox(
            QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel
        )
        self.sign_in_button = self.buttons.button(QDialogButtonBox.StandardButton.Ok)
        self.sign_in_button.setText("Sign in")
        self.buttons.accepted.connect(self.try_sign_in)
        self.buttons.rejected.connect(self.reject)

        layout = QVBoxLayout(self)
        layout.addWidget(heading)
        layout.addWidget(note)
        layout.addSpacing(6)
        layout.addLayout(form)
        layout.addWidget(self.error_label)
        layout.addWidget(self.buttons)
        (self.password_edit if username else self.username_edit).setFocus()

    def show_error(self, text: str) -> None:
        self.error_label.setText(text)
        self.error_label.setVisible(True)

    def try_sign_in(self) -> bool:
        """One attempt; on failure the reason stays in the dialog and the password clears."""
        username = self.username_edit.text().strip()
        password = self.password_edit.text()
        if not username or not password:
            self.show_error("Enter your username and password.")
            return False
        try:
            client = ApiClient(self.server_edit.text())
        except ValueError as exc:
            self.show_error(str(exc))
            return False
        QGuiApplication.setOverrideCursor(Qt.CursorShape.WaitCursor)
        try:
            user = client.login(username, password)
        except ApiError as exc:
            self.show_error(f"{exc.message[:1].upper()}{exc.message[1:]}.")
            self.password_edit.clear()
            self.password_edit.setFocus()
            return False
        except ServerUnreachable as exc:
            self.show_error(f"Cannot reach {exc.url}: {exc.reason}. Is `melfa serve` running?")
            return False
        finally:
            QGuiApplication.restoreOverrideCursor()
        self.client, self.user = client, user
        self.error_label.setVisible(False)
        self.accept()
        return True


__all__ = ["LoginDialog"]
