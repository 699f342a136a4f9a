"""The *Current position* panel: the hand's pose (X, Y, Z in mm; A, B, C in degrees), the
six joints (degrees) and the structure flags, live from the state messages."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QGridLayout, QGroupBox, QLabel

from melfa.desktop.style import ValueLabel, fmt_number
from melfa.live.messages import StateOut
from melfa.protocol import JOINT_NAMES, POSE_NAMES


class PositionBox(QGroupBox):
    def __init__(self) -> None:
        super().__init__("Current position")
        grid = QGridLayout(self)
        grid.setHorizontalSpacing(4)
        grid.setVerticalSpacing(2)
        self.pose_values: list[ValueLabel] = []
        self.joint_values: list[ValueLabel] = []
        for row, (caption, names, values) in enumerate(
            (
                ("Hand (mm, °)", POSE_NAMES, self.pose_values),
                ("Joints (°)", JOINT_NAMES, self.joint_values),
            )
        ):
            label = QLabel(caption)
            label.setObjectName("muted")
            grid.addWidget(label, 2 * row + 1, 0)
            for i, name in enumerate(names):
                head = QLabel(f"<b>{name}</b>")
                head.setAlignment(Qt.AlignmentFlag.AlignCenter)
                grid.addWidget(head, 2 * row, i + 1)
                value = ValueLabel(mono=True)
                value.setAccessibleName(f"{caption.split()[0]} {name}")
                values.append(value)
                grid.addWidget(value, 2 * row + 1, i + 1)
                grid.setColumnStretch(i + 1, 1)
        self.flags_label = QLabel("Flags: —")
        self.flags_label.setObjectName("muted")
        grid.addWidget(self.flags_label, 4, 0, 1, 7)

    def show_state(self, state: StateOut) -> None:
        for labels, values in ((self.pose_values, state.pose), (self.joint_values, state.joints)):
            for i, label in enumerate(labels):
                label.setText(fmt_number(values[i]) if values and i < len(values) else "—")
        flags = state.flags
        self.flags_label.setText(
            f"Flags (FL1, FL2): ({flags[0]}, {flags[1]})"
            if flags and len(flags) >= 2
            else "Flags: —"
        )


__all__ = ["PositionBox"]
