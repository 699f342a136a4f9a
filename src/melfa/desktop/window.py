"""The main window: files and commands on the left, the live robot on the right, the
activity log below, and a STOP button that is always there and always enabled.

Widgets only: every action goes to the `Presenter`, every dialog through `Dialogs`.
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt
from PySide6.QtGui import QCloseEvent, QFont, QFontDatabase, QKeySequence, QShortcut
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QFormLayout,
    QFrame,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QMainWindow,
    QPlainTextEdit,
    QPushButton,
    QScrollArea,
    QSizePolicy,
    QSpinBox,
    QTabWidget,
    QTreeWidget,
    QTreeWidgetItem,
    QVBoxLayout,
    QWidget,
)

from melfa.desktop.api import PRIVATE_TARGET, TARGET_LABELS, CheckResult, Severity
from melfa.desktop.dialogs import Dialogs, Notice
from melfa.desktop.files import FileKind
from melfa.desktop.live import FeedStatus
from melfa.desktop.messages import JOINT_NAMES, POSE_NAMES, LinkStatus, RobotState
from melfa.desktop.presenter import Presenter

LINK_STYLE = {
    LinkStatus.CONNECTED: ("ok", "Connected"),
    LinkStatus.CONNECTING: ("warn", "Connecting…"),
    LinkStatus.RECONNECTING: ("warn", "Reconnecting…"),
    LinkStatus.LOST: ("bad", "Link lost"),
    LinkStatus.CLOSED: ("bad", "Link closed"),
    LinkStatus.UNKNOWN: ("idle", "Unknown"),
}
FILE_FILTERS = {
    FileKind.PROGRAM: "MELFA BASIC IV programs (*.MB4 *.mb4);;All files (*)",
    FileKind.POINTS: "Points files (*.POS *.pos);;All files (*)",
}
LOG_LINES = 500

STYLE = """
QMainWindow, QDialog { background: #f4f5f7; }
QGroupBox {
    background: #ffffff; border: 1px solid #d6d9de; border-radius: 6px;
    margin-top: 14px; padding: 12px 10px 10px 10px; font-weight: 600;
}
QGroupBox::title { subcontrol-origin: margin; left: 10px; padding: 0 4px; color: #2b3440; }
QLabel { font-weight: normal; }
QLabel#heading { font-size: 15pt; font-weight: 600; color: #1f2630; }
QLabel#muted, QLabel#unit { color: #6b7480; }
QLabel#error { color: #b71c1c; font-weight: 600; }
QFrame#header { background: #263238; border-radius: 6px; }
QFrame#header QLabel { color: #eceff1; }
QLabel#title { font-size: 16pt; font-weight: 700; color: #ffffff; }
QLabel#pill { border-radius: 11px; padding: 3px 12px; font-weight: 600; }
QLabel#pill[level="ok"] { background: #2e7d32; color: white; }
QLabel#pill[level="warn"] { background: #f9a825; color: #1f2630; }
QLabel#pill[level="bad"] { background: #c62828; color: white; }
QLabel#pill[level="idle"] { background: #78909c; color: white; }
QLabel#value {
    background: #f7f9fb; border: 1px solid #dfe3e8; border-radius: 4px;
    padding: 3px 8px; color: #111820;
}
QLabel#value[level="running"] { color: #1b5e20; font-weight: 700; background: #e8f5e9; }
QLabel#value[level="alarm"] { color: #b71c1c; font-weight: 700; background: #ffebee; }
QTabWidget::pane { border: 1px solid #d6d9de; border-radius: 4px; top: -1px; background: white; }
QTabBar::tab {
    padding: 5px 14px; border: 1px solid #d6d9de; border-bottom: none;
    border-top-left-radius: 4px; border-top-right-radius: 4px; background: #eef1f4;
}
QTabBar::tab:selected { background: white; font-weight: 600; }
QPushButton {
    padding: 6px 14px; border: 1px solid #b8bec6; border-radius: 4px; background: #ffffff;
}
QPushButton:hover { background: #eef1f4; }
QPushButton:disabled { color: #9aa1a9; background: #f1f2f4; }
QPushButton#primary { background: #1565c0; color: white; border-color: #0d47a1; font-weight: 600; }
QPushButton#primary:hover { background: #1976d2; }
QPushButton#primary:disabled { background: #90a4bf; border-color: #90a4bf; }
QPushButton#stop {
    background: #d32f2f; color: white; border: 2px solid #8e0000; border-radius: 8px;
    font-size: 20pt; font-weight: 800; letter-spacing: 2px;
}
QPushButton#stop:hover { background: #e53935; }
QPushButton#stop:pressed { background: #b71c1c; }
QLineEdit { padding: 4px 6px; border: 1px solid #b8bec6; border-radius: 4px; background: white; }
QLineEdit[readOnly="true"] { background: #f7f9fb; }
QTreeWidget, QPlainTextEdit { border: 1px solid #d6d9de; border-radius: 4px; background: white; }
QStatusBar { background: #e9ecef; }
"""


def _fmt(value: float | None, digits: int = 2) -> str:
    return "—" if value is None else f"{value:,.{digits}f}".replace(",", " ")


def _yes_no(value: bool | None, yes: str = "On", no: str = "Off") -> str:
    return "—" if value is None else (yes if value else no)


class ValueLabel(QLabel):
    """A framed read-only value in a fixed-width font."""

    def __init__(self, text: str = "—", mono: bool = False) -> None:
        super().__init__(text)
        self.setObjectName("value")
        self.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        if mono:
            font = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
            font.setPointSizeF(max(font.pointSizeF(), 12.0))
            self.setFont(font)
            self.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            self.setMinimumWidth(110)


class MainWindow(QMainWindow):
    def __init__(
        self,
        presenter: Presenter,
        dialogs: Dialogs,
        on_closed: Callable[[], None] | None = None,
    ) -> None:
        super().__init__()
        self.presenter = presenter
        self.dialogs = dialogs
        self.on_closed = on_closed
        client = presenter.client
        user = client.user.username if client.user else "?"
        self.setWindowTitle(f"melfa desktop — {user} @ {client.server}")
        self.setStyleSheet(STYLE)
        self.resize(1080, 720)

        central = QWidget()
        root = QVBoxLayout(central)
        root.setContentsMargins(12, 12, 12, 6)
        root.setSpacing(10)
        root.addWidget(self._header(user, client.server, client.user.role if client.user else ""))

        body = QHBoxLayout()
        body.setSpacing(12)
        left = QVBoxLayout()
        left.addWidget(self._program_box(), 3)
        left.addWidget(self._exec_box())
        # The right column scrolls when the screen is short (a 1366×700 laptop).
        right_panel = QWidget()
        right = QVBoxLayout(right_panel)
        right.setContentsMargins(0, 0, 4, 0)
        right.addWidget(self._robot_box())
        right.addWidget(self._control_box())
        right.addWidget(self._position_box())
        right.addStretch(1)
        scroll = QScrollArea()
        scroll.setWidget(right_panel)
        scroll.setWidgetResizable(True)
        scroll.setFrameShape(QFrame.Shape.NoFrame)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        body.addLayout(left, 11)
        body.addWidget(scroll, 9)
        root.addLayout(body, 1)
        root.addWidget(self._log_box())
        self.setCentralWidget(central)

        self.feed_label = QLabel("Live feed: starting")
        self.statusBar().addPermanentWidget(self.feed_label)
        self.statusBar().showMessage(f"Signed in as {user}.")

        QShortcut(QKeySequence("Escape"), self, presenter.stop)  # STOP from anywhere
        self._bind()
        self.show_files()
        self.show_busy("")

    # --- layout --------------------------------------------------------------------------

    def _header(self, user: str, server: str, role: str) -> QFrame:
        header = QFrame()
        header.setObjectName("header")
        layout = QHBoxLayout(header)
        layout.setContentsMargins(16, 10, 10, 10)
        titles = QVBoxLayout()
        title = QLabel("MELFA RV-6S")
        title.setObjectName("title")
        sub = QLabel(f"{user} ({role}) on {server}")
        titles.addWidget(title)
        titles.addWidget(sub)
        layout.addLayout(titles)
        layout.addStretch(1)
        layout.addWidget(QLabel("Driving"))
        self.target_box = QComboBox()
        self.target_box.setAccessibleName("Which robot you drive")
        for target_id, label in TARGET_LABELS.items():
            self.target_box.addItem(label, target_id)
        self.target_box.setCurrentIndex(self.target_box.findData(self.presenter.client.target))
        self.target_box.currentIndexChanged.connect(self._target_chosen)
        layout.addWidget(self.target_box)
        layout.addSpacing(18)
        link_caption = QLabel("Robot link")
        self.link_pill = QLabel()
        self.link_pill.setObjectName("pill")
        self.link_pill.setAccessibleName("Robot link status")
        layout.addWidget(link_caption)
        layout.addWidget(self.link_pill)
        layout.addSpacing(18)
        self.stop_button = QPushButton("STOP")
        self.stop_button.setObjectName("stop")
        self.stop_button.setToolTip("Stop the robot now (Esc). Always available.")
        self.stop_button.setAccessibleName("Stop the robot")
        self.stop_button.setMinimumSize(190, 64)
        self.stop_button.setCursor(Qt.CursorShape.PointingHandCursor)
        layout.addWidget(self.stop_button)
        self.show_link(LinkStatus.UNKNOWN, "")
        return header

    def _target_chosen(self) -> None:
        target = str(self.target_box.currentData())
        self.presenter.choose_target(target)
        header = self.findChild(QFrame, "header")
        if header is not None:  # the header's colour says which robot: teal for the simulator
            colour = "#0d4f45" if target == PRIVATE_TARGET else ""
            header.setStyleSheet(f"QFrame#header {{ background: {colour}; }}" if colour else "")

    def _file_row(
        self, grid: QGridLayout, row: int, kind: FileKind
    ) -> tuple[QLineEdit, QPushButton]:
        label = QLabel(
            f"Program ({kind.value}):" if kind is FileKind.PROGRAM else f"Points ({kind.value}):"
        )
        edit = QLineEdit()
        edit.setReadOnly(True)
        edit.setPlaceholderText("No file chosen")
        edit.setAccessibleName(f"{kind.label} file")
        button = QPushButton("Choose…")
        button.setAccessibleName(f"Choose {kind.label}")
        label.setBuddy(button)
        grid.addWidget(label, row, 0)
        grid.addWidget(edit, row, 1)
        grid.addWidget(button, row, 2)
        return edit, button

    def _program_box(self) -> QGroupBox:
        box = QGroupBox("Program and points")
        layout = QVBoxLayout(box)
        grid = QGridLayout()
        grid.setColumnStretch(1, 1)
        self.program_edit, self.program_button = self._file_row(grid, 0, FileKind.PROGRAM)
        self.points_edit, self.points_button = self._file_row(grid, 1, FileKind.POINTS)
        layout.addLayout(grid)

        buttons = QHBoxLayout()
        self.check_button = QPushButton("Check")
        self.check_button.setToolTip("Check the program against the points (sends nothing)")
        self.load_button = QPushButton("Load into robot")
        self.load_button.setObjectName("primary")
        self.load_button.setToolTip("Check, then load program and points into slot 1")
        self.run_button = QPushButton("▶  Run program")
        self.run_button.setObjectName("primary")
        self.run_button.setToolTip("Run the program loaded in slot 1")
        buttons.addWidget(self.check_button)
        buttons.addStretch(1)
        buttons.addWidget(self.load_button)
        buttons.addWidget(self.run_button)
        layout.addLayout(buttons)

        self.tabs = QTabWidget()
        mono = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
        self.program_view = QPlainTextEdit()
        self.points_view = QPlainTextEdit()
        for view, empty in (
            (self.program_view, "Choose a program file to see it here."),
            (self.points_view, "Choose a points file to see it here."),
        ):
            view.setReadOnly(True)
            view.setFont(mono)
            view.setPlaceholderText(empty)
            view.setLineWrapMode(QPlainTextEdit.LineWrapMode.NoWrap)
        self.check_label = QLabel("Check results: not checked yet")
        self.check_label.setObjectName("muted")
        self.diagnostics = QTreeWidget()
        self.diagnostics.setColumnCount(3)
        self.diagnostics.setHeaderLabels(["Where", "Severity", "Message"])
        self.diagnostics.setRootIsDecorated(False)
        self.diagnostics.setAlternatingRowColors(True)
        self.diagnostics.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        header = self.diagnostics.header()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(True)
        check_page = QWidget()
        check_layout = QVBoxLayout(check_page)
        check_layout.setContentsMargins(6, 6, 6, 6)
        check_layout.addWidget(self.check_label)
        check_layout.addWidget(self.diagnostics, 1)
        self.tabs.addTab(self.program_view, "Program")
        self.tabs.addTab(self.points_view, "Points")
        self.tabs.addTab(check_page, "Check results")
        layout.addWidget(self.tabs, 1)
        return box

    def _exec_box(self) -> QGroupBox:
        box = QGroupBox("Single instruction")
        layout = QHBoxLayout(box)
        self.exec_edit = QLineEdit()
        self.exec_edit.setPlaceholderText("A MELFA BASIC statement, e.g. MOV P1 or HOPEN 1")
        self.exec_edit.setAccessibleName("Instruction")
        self.exec_button = QPushButton("Send")
        self.exec_button.setObjectName("primary")
        layout.addWidget(self.exec_edit, 1)
        layout.addWidget(self.exec_button)
        return box

    def _robot_box(self) -> QGroupBox:
        box = QGroupBox("Robot")
        form = QFormLayout(box)
        form.setLabelAlignment(Qt.AlignmentFlag.AlignRight)
        self.status_values: dict[str, ValueLabel] = {}
        for key, caption in (
            ("state", "Program state"),
            ("program", "Program"),
            ("line", "Line"),
            ("servo", "Servo"),
            ("override", "Override"),
            ("lease", "Operator"),
            ("alarm", "Alarm"),
        ):
            label = ValueLabel()
            self.status_values[key] = label
            if key == "alarm":
                label.setWordWrap(True)
                row = QHBoxLayout()
                row.addWidget(label, 1)
                self.reset_alarm_button = QPushButton("Reset alarm")
                self.reset_alarm_button.setToolTip("Clear the controller's error (RSTALRM)")
                row.addWidget(self.reset_alarm_button)
                form.addRow(f"{caption}:", row)
            else:
                form.addRow(f"{caption}:", label)
        return box

    def _control_box(self) -> QGroupBox:
        """Servo, speed override and step jog: what the thesis's client lacked."""
        box = QGroupBox("Servo, speed and jog")
        grid = QGridLayout(box)
        grid.setHorizontalSpacing(6)
        self.servo_on_button = QPushButton("Servo on")
        self.servo_off_button = QPushButton("Servo off")
        grid.addWidget(QLabel("Servo:"), 0, 0)
        grid.addWidget(self.servo_on_button, 0, 1)
        grid.addWidget(self.servo_off_button, 0, 2)
        self.override_spin = QSpinBox()
        self.override_spin.setRange(1, 100)
        self.override_spin.setValue(30)
        self.override_spin.setSuffix(" %")
        self.override_button = QPushButton("Apply")
        grid.addWidget(QLabel("Override:"), 1, 0)
        grid.addWidget(self.override_spin, 1, 1)
        grid.addWidget(self.override_button, 1, 2)
        self.jog_frame = QComboBox()
        for text, value in (("Base XYZ", "xyz"), ("Tool", "tool"), ("Joints", "joint")):
            self.jog_frame.addItem(text, value)
        grid.addWidget(QLabel("Jog frame:"), 2, 0)
        grid.addWidget(self.jog_frame, 2, 1, 1, 2)
        self.jog_buttons: dict[tuple[int, int], QPushButton] = {}
        row = QHBoxLayout()
        for axis in range(3):
            for direction in (-1, 1):
                button = QPushButton()
                button.setMinimumWidth(44)
                self.jog_buttons[(axis, direction)] = button
                row.addWidget(button)
        grid.addLayout(row, 3, 0, 1, 3)
        self._label_jog()
        return box

    def _label_jog(self) -> None:
        joint = self.jog_frame.currentData() == "joint"
        for (axis, direction), button in self.jog_buttons.items():
            name = f"J{axis + 1}" if joint else "XYZ"[axis]
            button.setText(f"{name}{'+' if direction > 0 else '−'}")
            button.setToolTip(f"One step {name} {'+' if direction > 0 else '-'}")

    def _position_box(self) -> QGroupBox:
        box = QGroupBox("Current position")
        grid = QGridLayout(box)
        grid.setHorizontalSpacing(8)
        grid.setVerticalSpacing(6)
        caption_pose = QLabel("Tool pose")
        caption_joints = QLabel("Joints")
        for caption in (caption_pose, caption_joints):
            caption.setObjectName("muted")
        grid.addWidget(caption_pose, 0, 0, 1, 3)
        grid.addWidget(caption_joints, 0, 4, 1, 3)
        self.pose_values: list[ValueLabel] = []
        self.joint_values: list[ValueLabel] = []
        for i, (pose_name, joint_name) in enumerate(zip(POSE_NAMES, JOINT_NAMES, strict=True)):
            row = i + 1
            pose_value = ValueLabel(mono=True)
            pose_value.setAccessibleName(f"Pose {pose_name}")
            joint_value = ValueLabel(mono=True)
            joint_value.setAccessibleName(f"Joint {joint_name}")
            self.pose_values.append(pose_value)
            self.joint_values.append(joint_value)
            unit = QLabel("mm" if i < 3 else "°")
            unit.setObjectName("unit")
            junit = QLabel("°")
            junit.setObjectName("unit")
            grid.addWidget(QLabel(f"<b>{pose_name}</b>"), row, 0)
            grid.addWidget(pose_value, row, 1)
            grid.addWidget(unit, row, 2)
            grid.addWidget(QLabel(f"<b>{joint_name}</b>"), row, 4)
            grid.addWidget(joint_value, row, 5)
            grid.addWidget(junit, row, 6)
        grid.setColumnMinimumWidth(3, 18)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(5, 1)
        self.flags_label = QLabel("Flags: —")
        self.flags_label.setObjectName("muted")
        grid.addWidget(self.flags_label, 7, 0, 1, 7)
        return box

    def _log_box(self) -> QGroupBox:
        box = QGroupBox("Activity")
        layout = QVBoxLayout(box)
        self.log = QPlainTextEdit()
        self.log.setReadOnly(True)
        self.log.setMaximumBlockCount(LOG_LINES)
        self.log.setFont(QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont))
        self.log.setFixedHeight(80)
        self.log.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        layout.addWidget(self.log)
        return box

    # --- wiring --------------------------------------------------------------------------

    def _bind(self) -> None:
        p = self.presenter
        self.stop_button.clicked.connect(p.stop)
        self.program_button.clicked.connect(lambda: self.choose(FileKind.PROGRAM))
        self.points_button.clicked.connect(lambda: self.choose(FileKind.POINTS))
        self.check_button.clicked.connect(p.check)
        self.load_button.clicked.connect(p.load)
        self.run_button.clicked.connect(p.run)
        self.reset_alarm_button.clicked.connect(p.reset_alarm)
        self.exec_button.clicked.connect(self._send_exec)
        self.exec_edit.returnPressed.connect(self._send_exec)
        self.servo_on_button.clicked.connect(lambda: p.servo(True))
        self.servo_off_button.clicked.connect(lambda: p.servo(False))
        self.override_button.clicked.connect(lambda: p.set_override(self.override_spin.value()))
        self.jog_frame.currentIndexChanged.connect(self._label_jog)
        for (axis, direction), button in self.jog_buttons.items():
            button.clicked.connect(
                lambda _=False, a=axis, d=direction: p.jog(self.jog_frame.currentData(), a, d)
            )
        p.attach(self)

    def choose(self, kind: FileKind) -> None:
        title = "Choose a program" if kind is FileKind.PROGRAM else "Choose a points file"
        path = self.dialogs.open_file(title, FILE_FILTERS[kind], self)
        if path is not None:
            self.presenter.choose(kind, path)

    def _send_exec(self) -> None:
        if self.presenter.exec_statement(self.exec_edit.text()):
            self.exec_edit.selectAll()

    def show_notice(self, notice: Notice) -> None:
        self.dialogs.show(notice, self)

    def show_files(self) -> None:
        p = self.presenter
        for chosen, edit, view in (
            (p.program, self.program_edit, self.program_view),
            (p.points, self.points_edit, self.points_view),
        ):
            if chosen is None:
                edit.clear()
                edit.setToolTip("")
                view.clear()
                continue
            lines = chosen.text.count("\n") + (not chosen.text.endswith("\n"))
            edit.setText(f"{chosen.path.name}   ({lines} lines, in {chosen.path.parent})")
            edit.setCursorPosition(0)
            edit.setToolTip(str(chosen.path))
            if view.toPlainText() != chosen.text:
                view.setPlainText(chosen.text)
                self.tabs.setCurrentWidget(view)  # show what was just chosen
        self.show_busy(p.busy)

    def show_busy(self, what: str) -> None:
        idle = not what
        has_program = self.presenter.program is not None
        for button in (
            self.program_button,
            self.points_button,
            self.run_button,
            self.exec_button,
            self.reset_alarm_button,
            self.servo_on_button,
            self.servo_off_button,
            self.override_button,
            *self.jog_buttons.values(),
        ):
            button.setEnabled(idle)
        self.check_button.setEnabled(idle and has_program)
        self.load_button.setEnabled(idle and has_program)
        self.stop_button.setEnabled(True)  # never disabled
        if what:
            self.statusBar().showMessage(f"{what}…")

    def show_check(self, result: CheckResult) -> None:
        self.diagnostics.clear()
        for source, diags in (("", result.program), ("points ", result.points)):
            for d in diags:
                item = QTreeWidgetItem(
                    [f"{source}{d.line}:{d.column}", d.severity.value, d.message]
                )
                if d.suggestion:
                    item.setToolTip(2, d.suggestion)
                if d.severity is Severity.ERROR:
                    item.setForeground(1, Qt.GlobalColor.darkRed)
                    font = QFont(item.font(1))
                    font.setBold(True)
                    item.setFont(1, font)
                self.diagnostics.addTopLevelItem(item)
        errors = len(result.program_errors) + len(result.points_errors)
        total = len(result.program) + len(result.points)
        self.tabs.setTabText(2, f"Check results ({total})" if total else "Check results")
        if errors:
            self.tabs.setCurrentIndex(2)
        self.check_label.setText(
            "Check results: no findings"
            if not total
            else f"Check results: {errors} error(s), {total - errors} warning(s)/note(s)"
        )

    def show_link(self, status: LinkStatus, detail: str) -> None:
        level, text = LINK_STYLE[status]
        self.link_pill.setText(text)
        self.link_pill.setToolTip(detail or text)
        self.link_pill.setProperty("level", level)
        self.link_pill.style().unpolish(self.link_pill)
        self.link_pill.style().polish(self.link_pill)

    def show_feed(self, status: FeedStatus, detail: str) -> None:
        self.feed_label.setText(f"Live feed: {status.value}")
        self.feed_label.setToolTip(detail)

    def show_state(self, state: RobotState) -> None:
        for labels, values in ((self.pose_values, state.pose), (self.joint_values, state.joints)):
            for i, label in enumerate(labels):
                label.setText(_fmt(values[i]) if values and i < len(values) else "—")
        flags = state.flags
        self.flags_label.setText(
            f"Flags: ({flags[0]}, {flags[1]})" if flags and len(flags) >= 2 else "Flags: —"
        )
        v = self.status_values
        if state.running is None:
            v["state"].setText("—")
        else:
            v["state"].setText("Running" if state.running else "Stopped")
        if state.busy:
            v["state"].setText(f"Busy: {state.busy}")
        level = "running" if state.running else ("alarm" if state.alarm else "")
        if v["state"].property("level") != level:
            v["state"].setProperty("level", level)
            v["state"].style().unpolish(v["state"])
            v["state"].style().polish(v["state"])
        v["program"].setText(state.program or "—")
        # The line of the student's file (the server maps the controller's step numbers).
        upload = self.presenter.last_upload
        source = upload.step_lines.get(state.line) if upload and state.line else None
        if state.line is None or not state.line:
            v["line"].setText("—")
        elif source is not None:
            v["line"].setText(f"{source} (step {state.line})")
        else:
            v["line"].setText(f"step {state.line}")
        v["servo"].setText(_yes_no(state.servo))
        v["override"].setText("—" if state.override is None else f"{state.override} %")
        v["alarm"].setText(f"{state.alarm.number}: {state.alarm.text}" if state.alarm else "None")
        v["alarm"].setToolTip(v["alarm"].text())  # never clipped: the whole text on hover
        v["lease"].setText(state.lease_holder or "Nobody")

    def append_log(self, line: str) -> None:
        self.log.appendPlainText(line)

    def show_status(self, text: str) -> None:
        self.statusBar().showMessage(text)

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 (Qt's name)
        self.presenter.shutdown()
        super().closeEvent(event)
        if self.on_closed is not None:
            self.on_closed()


__all__ = ["MainWindow"]
