"""The jog pad: six buttons and the thesis's keys (W/S ±X, A/D ±Y, ↑/↓ ±Z), hold-to-move.

A jog moves only while its key or button is held: the pad asks the presenter to start on
key (or mouse) down and to stop on key up, when it loses the keyboard focus, when the window
is deactivated and when the frame changes. The keyboard's auto-repeat is ignored (the
presenter's heartbeat keeps a held jog alive, not the repeat), so a held key is one jog.
X's auto-repeat arrives as a key-up and a key-down at the same instant, which Qt does not
always mark as a repeat; so a key-up waits `REPEAT_GRACE_MS` for its key to come down
again before the jog stops (a real let-go stops that much later; focus loss stops at once).
The pad takes the keyboard when clicked; its border says so, and W, A, S, D and the arrows
then jog instead of typing.
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import QEvent, QObject, Qt, QTimer
from PySide6.QtGui import QFocusEvent, QKeyEvent
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QFrame,
    QGridLayout,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QVBoxLayout,
)

from melfa.desktop.words import jog_label

KEYS: dict[Qt.Key, tuple[int, int, str]] = {
    Qt.Key.Key_W: (0, 1, "W"),
    Qt.Key.Key_S: (0, -1, "S"),
    Qt.Key.Key_A: (1, 1, "A"),
    Qt.Key.Key_D: (1, -1, "D"),
    Qt.Key.Key_Up: (2, 1, "↑"),
    Qt.Key.Key_Down: (2, -1, "↓"),
}
"""key → (slot within the axis group, direction, the key's name on the button)."""
FRAMES = (("Base XYZ", "xyz"), ("Tool XYZ", "tool"), ("Joints", "joint"))
HINT_IDLE = "Click the pad, then hold W/S, A/D or ↑/↓ (or hold a button): moves only while held."
HINT_KEYS = "Keys jog now: hold W/S, A/D or ↑/↓. Let go to stop. Esc is STOP."
REPEAT_GRACE_MS = 30
"""How long a key-up waits for the same key's auto-repeat key-down (sent with it at once by
X) before it stops the jog: short against the server's 0.3 s heartbeat bound."""


class JogPad(QFrame):
    """Frame and axis choice, the six hold-to-move buttons, and the keys while focused."""

    def __init__(
        self,
        press: Callable[[str, int, int], object],
        release: Callable[[], object],
        step: Callable[[str, int, int], object],
    ) -> None:
        super().__init__()
        self.setObjectName("jogpad")
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setAccessibleName("Jog pad: hold a key or button to move")
        self._press, self._release, self._step = press, release, step
        self._held_key: Qt.Key | None = None
        self._let_go = QTimer(self)
        self._let_go.setSingleShot(True)
        self._let_go.setInterval(REPEAT_GRACE_MS)
        self._let_go.timeout.connect(self._key_let_go)

        self.frame_box = QComboBox()
        self.frame_box.setAccessibleName("Jog frame")
        for text, value in FRAMES:
            self.frame_box.addItem(text, value)
        self.group_box = QComboBox()
        self.group_box.setAccessibleName("Joints the keys move")
        self.group_box.addItem("J1–J3", 0)
        self.group_box.addItem("J4–J6", 3)
        self.step_box = QCheckBox("One step per press")
        self.step_box.setToolTip("Each press moves one small step instead of moving while held")
        top = QHBoxLayout()
        keys = QLabel("&Jog")  # Alt+J gives the pad the keyboard
        keys.setBuddy(self)
        keys.setStyleSheet("font-weight: 600;")
        top.addWidget(keys)
        top.addSpacing(8)
        top.addWidget(QLabel("Frame:"))
        top.addWidget(self.frame_box)
        top.addWidget(self.group_box)
        top.addStretch(1)
        top.addWidget(self.step_box)

        self.buttons: dict[tuple[int, int], QPushButton] = {}
        grid = QGridLayout()
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(4)
        for key, (slot, direction, _name) in KEYS.items():
            button = QPushButton()
            button.setObjectName("jog")
            button.setFocusPolicy(Qt.FocusPolicy.NoFocus)  # the pad keeps the keyboard
            button.pressed.connect(lambda s=slot, d=direction: self._button_down(s, d))
            button.released.connect(lambda s=slot, d=direction: self._button_up(s, d))
            self.buttons[(slot, direction)] = button
            grid.addWidget(button, 0 if direction > 0 else 1, slot)
            del key
        self.hint = QLabel(HINT_IDLE)
        self.hint.setObjectName("muted")
        self.hint.setWordWrap(True)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 4, 6, 4)
        layout.setSpacing(4)
        layout.addLayout(top)
        layout.addLayout(grid)
        layout.addWidget(self.hint)
        self.frame_box.currentIndexChanged.connect(self._frame_changed)
        self.group_box.currentIndexChanged.connect(self._frame_changed)
        self._frame_changed()

    # --- what a key means now -------------------------------------------------------------

    @property
    def frame(self) -> str:
        return str(self.frame_box.currentData())

    def axis_of(self, slot: int) -> int:
        """Axis 0–5 for a key's slot: J4–J6 when the joints group says so."""
        return slot + (int(self.group_box.currentData()) if self.frame == "joint" else 0)

    def _frame_changed(self) -> None:
        self._release_held()
        self.group_box.setVisible(self.frame == "joint")
        for (slot, direction), button in self.buttons.items():
            name = next(n for s, d, n in KEYS.values() if (s, d) == (slot, direction))
            label = jog_label(self.frame, self.axis_of(slot), direction)
            button.setText(f"{label}   {name}")
            button.setToolTip(f"Hold to move {label} (key {name} while the pad has the keyboard)")
            button.setAccessibleName(f"Jog {label}")

    # --- pressing -------------------------------------------------------------------------

    def _down(self, slot: int, direction: int) -> None:
        axis = self.axis_of(slot)
        if self.step_box.isChecked():
            self._step(self.frame, axis, direction)
        else:
            self._press(self.frame, axis, direction)

    def _button_down(self, slot: int, direction: int) -> None:
        self.setFocus(Qt.FocusReason.MouseFocusReason)
        self._held_key = None
        self._down(slot, direction)

    def _button_up(self, slot: int, direction: int) -> None:
        self._release()

    def _release_held(self) -> None:
        self._let_go.stop()
        self._held_key = None
        self._release()

    def _key_let_go(self) -> None:
        """The held key stayed up for `REPEAT_GRACE_MS`: it was let go, not repeated."""
        key = self._held_key
        if key is not None:
            slot, direction, _ = KEYS[key]
            self.buttons[(slot, direction)].setDown(False)
            self._release_held()

    def keyPressEvent(self, event: QKeyEvent) -> None:  # noqa: N802 (Qt's name)
        key = Qt.Key(event.key())
        if key not in KEYS:
            super().keyPressEvent(event)
            return
        event.accept()
        if event.isAutoRepeat() or key == self._held_key:
            self._let_go.stop()  # the key-up just before was the repeat's, not a let-go
            return  # the heartbeat keeps a held jog alive, not the keyboard's repeat
        self._let_go.stop()
        slot, direction, _ = KEYS[key]
        self._held_key = key
        self.buttons[(slot, direction)].setDown(True)
        self._down(slot, direction)

    def keyReleaseEvent(self, event: QKeyEvent) -> None:  # noqa: N802 (Qt's name)
        key = Qt.Key(event.key())
        if key not in KEYS:
            super().keyReleaseEvent(event)
            return
        event.accept()
        if event.isAutoRepeat():
            return
        if key == self._held_key:
            self._let_go.start()  # stops unless the same key comes down again at once
            return
        slot, direction, _ = KEYS[key]
        self.buttons[(slot, direction)].setDown(False)

    def focusInEvent(self, event: QFocusEvent) -> None:  # noqa: N802 (Qt's name)
        self.hint.setText(HINT_KEYS)
        super().focusInEvent(event)

    def focusOutEvent(self, event: QFocusEvent) -> None:  # noqa: N802 (Qt's name)
        self.hint.setText(HINT_IDLE)
        for button in self.buttons.values():
            button.setDown(False)
        self._release_held()  # a key held while the focus left is not let go to us
        super().focusOutEvent(event)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:  # noqa: N802 (Qt's name)
        """Installed on the window: a window that is no longer active stops the jog."""
        if event.type() == QEvent.Type.WindowDeactivate:
            self._release_held()
        return False

    def set_buttons_enabled(self, idle: bool) -> None:
        """Buttons follow the presenter's busy state; the pad itself stays focusable."""
        for button in self.buttons.values():
            button.setEnabled(idle)


__all__ = ["FRAMES", "KEYS", "JogPad"]
