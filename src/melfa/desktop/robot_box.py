"""The *Robot* panel: what the robot does now (in the sentence the browser shows too), the
servo, the speed override, who holds control, and the alarm with its one-click fix.

Its own module because it is the window's one panel that reads the robot's state as words;
the pose and joints are `position`'s, and the window wires the fix button.
"""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QGridLayout, QGroupBox, QHBoxLayout, QLabel, QPushButton

from melfa.desktop.messages import alarm_said, offered_fix
from melfa.desktop.style import ValueLabel, on_off, set_level
from melfa.desktop.words import Loaded, activity_text, control_text
from melfa.live.messages import StateOut
from melfa.protocol.advice import FIX_LABELS
from melfa.vocab.activity import Activity
from melfa.vocab.lease import CONTROL_WORDS

ACTIVITY_LEVEL = {
    Activity.ALARM: "alarm",
    Activity.OFFLINE: "alarm",
    Activity.RUNNING: "running",
    Activity.IDLE: "",
}
"""How the activity's value is coloured (`style.STYLE`); any other activity is busy."""


def _caption(text: str) -> QLabel:
    label = QLabel(text)
    label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
    return label


class RobotBox(QGroupBox):
    def __init__(self) -> None:
        super().__init__("Robot")
        grid = QGridLayout(self)
        grid.setHorizontalSpacing(8)
        grid.setVerticalSpacing(4)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        self.status_values: dict[str, ValueLabel] = {
            key: ValueLabel() for key in ("activity", "servo", "override", "lease", "alarm")
        }
        v = self.status_values
        v["activity"].setAccessibleName("What the robot does now")
        v["alarm"].setWordWrap(True)
        v["alarm"].setMinimumHeight(26)
        v["lease"].setWordWrap(True)
        grid.addWidget(_caption("Now:"), 0, 0)
        grid.addWidget(v["activity"], 0, 1, 1, 3)
        grid.addWidget(_caption("Servo:"), 1, 0)
        grid.addWidget(v["servo"], 1, 1)
        grid.addWidget(_caption("Speed:"), 1, 2)
        grid.addWidget(v["override"], 1, 3)
        grid.addWidget(_caption(CONTROL_WORDS.control), 2, 0)
        grid.addWidget(v["lease"], 2, 1, 1, 3)
        grid.addWidget(_caption("Alarm:"), 3, 0)
        alarm_row = QHBoxLayout()
        alarm_row.addWidget(v["alarm"], 1)
        self.alarm_fix_button = QPushButton("Reset alarm")
        self.alarm_fix_button.setObjectName("fix")
        self.alarm_fix_button.setVisible(False)
        alarm_row.addWidget(self.alarm_fix_button)
        grid.addLayout(alarm_row, 3, 1, 1, 3)

    def show_state(
        self, state: StateOut, loaded: Loaded | None, me: str, queued: bool = False
    ) -> None:
        """``loaded``: the file this client loaded (its lines, not step numbers); ``me``: the
        user signed in here (control held by them reads *you*); ``queued``: someone waits
        in the lab robot's queue (free control is the queue's to give)."""
        v = self.status_values
        v["activity"].setText(activity_text(state, loaded))
        set_level(v["activity"], ACTIVITY_LEVEL.get(state.activity, "busy"))
        v["servo"].setText(on_off(state.servo))
        v["override"].setText("—" if state.override is None else f"{state.override} %")
        v["lease"].setText(control_text(state, me, queued))
        alarm = state.alarm
        v["alarm"].setText(alarm_said(alarm) if alarm else "None")
        v["alarm"].setToolTip(alarm_said(alarm) if alarm else "")
        set_level(v["alarm"], "alarm" if alarm else "")
        fix = offered_fix(alarm.fix) if alarm else None
        self.alarm_fix_button.setVisible(fix is not None)
        if fix is not None:
            self.alarm_fix_button.setText(FIX_LABELS[fix])


__all__ = ["ACTIVITY_LEVEL", "RobotBox"]
