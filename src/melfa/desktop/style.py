"""The desktop client's look: one style sheet (Qt's CSS), the link pill's levels, the
framed value labels and how numbers are written in them."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QFontDatabase, QFontMetrics
from PySide6.QtWidgets import QLabel, QWidget

from melfa.vocab.link import LinkStatus

LINK_LEVEL: dict[LinkStatus | None, str] = {
    LinkStatus.CONNECTED: "ok",
    LinkStatus.CONNECTING: "warn",
    LinkStatus.RECONNECTING: "warn",
    LinkStatus.LOST: "bad",
    LinkStatus.CLOSED: "bad",
    None: "idle",  # not known yet
}

STYLE = """
QMainWindow, QDialog { background: #f4f5f7; }
QGroupBox {
    background: #ffffff; border: 1px solid #d6d9de; border-radius: 6px;
    margin-top: 12px; padding: 8px 8px 6px 8px; font-weight: 600;
}
QGroupBox::title { subcontrol-origin: margin; left: 10px; padding: 0 4px; color: #2b3440; }
QLabel { font-weight: normal; }
QLabel#heading { font-size: 15pt; font-weight: 600; color: #1f2630; }
QLabel#muted, QLabel#unit { color: #6b7480; }
QLabel#error { color: #b71c1c; font-weight: 600; }
QFrame#header { background: #263238; border-radius: 6px; }
QFrame#header QLabel { color: #eceff1; }
QLabel#title { font-size: 15pt; font-weight: 700; color: #ffffff; }
QLabel#pill { border-radius: 11px; padding: 3px 12px; font-weight: 600; }
QLabel#pill[level="ok"] { background: #2e7d32; color: white; }
QLabel#pill[level="warn"] { background: #f9a825; color: #1f2630; }
QLabel#pill[level="bad"] { background: #c62828; color: white; }
QLabel#pill[level="idle"] { background: #78909c; color: white; }
QLabel#value {
    background: #f7f9fb; border: 1px solid #dfe3e8; border-radius: 4px;
    padding: 3px 8px; color: #111820;
}
QLabel#value[mono="true"] { padding: 2px 4px; }
QLabel#value[level="busy"] { color: #0d47a1; font-weight: 700; background: #e3f2fd; }
QLabel#value[level="running"] { color: #1b5e20; font-weight: 700; background: #e8f5e9; }
QLabel#value[level="alarm"] { color: #b71c1c; font-weight: 700; background: #ffebee; }
QTabWidget::pane { border: 1px solid #d6d9de; border-radius: 4px; top: -1px; background: white; }
QTabBar::tab {
    padding: 5px 14px; border: 1px solid #d6d9de; border-bottom: none;
    border-top-left-radius: 4px; border-top-right-radius: 4px; background: #eef1f4;
}
QTabBar::tab:selected { background: white; font-weight: 600; }
QPushButton {
    padding: 4px 12px; border: 1px solid #b8bec6; border-radius: 4px; background: #ffffff;
}
QPushButton#jog { padding: 6px 8px; font-weight: 600; }
QPushButton#jog:pressed, QPushButton#jog[level="held"] { background: #bbdefb; }
QFrame#jogpad { border: 2px solid #e3e6ea; border-radius: 6px; }
QFrame#jogpad:focus { border: 2px solid #1565c0; background: #f3f8fe; }
QPushButton#fix { background: #fff3e0; border-color: #ef6c00; font-weight: 600; }
QPushButton:hover { background: #eef1f4; }
QPushButton:disabled { color: #9aa1a9; background: #f1f2f4; }
QPushButton#primary { background: #1565c0; color: white; border-color: #0d47a1; font-weight: 600; }
QPushButton#primary:hover { background: #1976d2; }
QPushButton#primary:disabled { background: #90a4bf; border-color: #90a4bf; }
QPushButton#stop {
    background: #d32f2f; color: white; border: 2px solid #8e0000; border-radius: 8px;
    font-size: 18pt; font-weight: 800; letter-spacing: 2px;
}
QPushButton#stop:hover { background: #e53935; }
QPushButton#claim { background: #23824a; color: white; font-weight: bold; padding: 4px 14px; }
QPushButton#stop:pressed { background: #b71c1c; }
QLineEdit { padding: 4px 6px; border: 1px solid #b8bec6; border-radius: 4px; background: white; }
QLineEdit[readOnly="true"] { background: #f7f9fb; }
QTreeWidget, QPlainTextEdit { border: 1px solid #d6d9de; border-radius: 4px; background: white; }
QStatusBar { background: #e9ecef; }
"""


def fmt_number(value: float | None, digits: int = 2) -> str:
    return "—" if value is None else f"{value:,.{digits}f}".replace(",", " ")


def on_off(value: bool | None, yes: str = "On", no: str = "Off") -> str:
    return "—" if value is None else (yes if value else no)


def set_level(widget: QWidget, level: str) -> None:
    """A style-sheet level (``running``, ``alarm``…) that re-polishes only when it changes."""
    if widget.property("level") != level:
        widget.setProperty("level", level)
        widget.style().unpolish(widget)
        widget.style().polish(widget)


class ValueLabel(QLabel):
    """A framed read-only value; numbers in a fixed-width font, right-aligned."""

    def __init__(self, text: str = "—", mono: bool = False) -> None:
        super().__init__(text)
        self.setObjectName("value")
        self.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        if mono:
            font = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
            font.setPointSizeF(max(font.pointSizeF(), 10.5))
            self.setFont(font)
            self.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            self.setProperty("mono", True)
            # Wide enough for "-1234.56" whatever the screen's DPI: never clipped.
            self.setMinimumWidth(QFontMetrics(font).horizontalAdvance("-1234.56") + 12)


__all__ = ["LINK_LEVEL", "STYLE", "ValueLabel", "fmt_number", "on_off", "set_level"]
