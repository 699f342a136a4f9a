"""The main window: files, instruction and activity log on the left; the robot's state, the
servo, speed and jog pad, and the live position on the right; a STOP button that is always
there and always enabled. Laid out to fit a 1366×700 laptop screen without scrolling.

Widgets only: every action goes to the `Presenter`, every dialog through `Dialogs`.
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt
from PySide6.QtGui import (
    QCloseEvent,
    QColor,
    QFont,
    QFontDatabase,
    QKeySequence,
    QShortcut,
    QTextCursor,
    QTextFormat,
)
from PySide6.QtWidgets import (
    QAbstractItemView,
    QApplication,
    QComboBox,
    QFrame,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QMainWindow,
    QPlainTextEdit,
    QProgressBar,
    QPushButton,
    QSizePolicy,
    QSpinBox,
    QTabWidget,
    QTextEdit,
    QTreeWidget,
    QTreeWidgetItem,
    QVBoxLayout,
    QWidget,
)

from melfa.desktop.api import (
    PRIVATE_TARGET,
    TARGET_LABELS,
    CheckResult,
    Severity,
    WorkspaceInfo,
)
from melfa.desktop.dialogs import Dialogs, Notice
from melfa.desktop.files import FileKind
from melfa.desktop.hold import JogKey
from melfa.desktop.jogpad import JogPad
from melfa.desktop.live import FeedStatus
from melfa.desktop.messages import alarm_said
from melfa.desktop.position import PositionBox
from melfa.desktop.presenter import FIXES_OFFERED, Presenter
from melfa.desktop.style import LINK_LEVEL, STYLE, ValueLabel, on_off, set_level
from melfa.desktop.words import (
    activity_text,
    control_text,
    count,
    file_line,
    jog_label,
    link_words,
)
from melfa.live.messages import StateOut
from melfa.protocol import OVERRIDE_PERCENT
from melfa.protocol.advice import FIX_LABELS
from melfa.vocab.activity import Activity
from melfa.vocab.link import LinkStatus

FILE_FILTERS = {
    FileKind.PROGRAM: "MELFA BASIC IV programs (*.MB4 *.mb4);;All files (*)",
    FileKind.POINTS: "Points files (*.POS *.pos);;All files (*)",
}
LOG_LINES = 500
FILES_SOURCE = "Files on this computer"
FEED_WORDS = {
    FeedStatus.CONNECTING: "Live updates: connecting…",
    FeedStatus.CONNECTED: "Live updates: on",
    FeedStatus.DISCONNECTED: "Live updates: reconnecting…",
    FeedStatus.REFUSED: "Live updates: refused (sign in again)",
    FeedStatus.CLOSED: "Live updates: off",
}
ACTIVITY_LEVEL = {
    Activity.ALARM: "alarm",
    Activity.OFFLINE: "alarm",
    Activity.RUNNING: "running",
    Activity.IDLE: "",
}


class RefreshingCombo(QComboBox):
    """A combo box that asks for a fresh list each time it opens (new workspaces appear)."""

    def __init__(self, refresh: Callable[[], object]) -> None:
        super().__init__()
        self._refresh = refresh

    def showPopup(self) -> None:  # noqa: N802 (Qt's name)
        self._refresh()
        super().showPopup()


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
        self.resize(1366, 700)

        central = QWidget()
        root = QVBoxLayout(central)
        root.setContentsMargins(10, 8, 10, 4)
        root.setSpacing(6)
        root.addWidget(self._header(user, client.server, client.user.role if client.user else ""))

        body = QHBoxLayout()
        body.setSpacing(10)
        left = QVBoxLayout()
        left.setSpacing(4)
        left.addWidget(self._program_box(), 1)
        left.addWidget(self._exec_box())
        left.addWidget(self._log_box())
        right = QVBoxLayout()
        right.setSpacing(4)
        right.addWidget(self._robot_box())
        right.addWidget(self._control_box())
        self.position = PositionBox()
        self.pose_values, self.joint_values = self.position.pose_values, self.position.joint_values
        right.addWidget(self.position)
        right.addStretch(1)
        body.addLayout(left, 10)
        body.addLayout(right, 11)
        root.addLayout(body, 1)
        self.setCentralWidget(central)

        self.progress = QProgressBar()
        self.progress.setRange(0, 100)
        self.progress.setMaximumWidth(220)
        self.progress.setFormat("Sending %p %")
        self.progress.setVisible(False)
        self.feed_label = QLabel(FEED_WORDS[FeedStatus.CONNECTING])
        self._busy_text = ""
        self._followed_line: int | None = None
        """The running line last scrolled into view (scrolled again only when it moves)."""
        self.queue_label = QLabel("")
        self.queue_label.setAccessibleName("Lab robot queue")
        self.claim_button = QPushButton("Claim the arm and run")
        self.claim_button.setObjectName("claim")
        self.claim_button.setToolTip("Your turn at the lab robot: claim it before the time ends")
        self.claim_button.setVisible(False)
        self.claim_button.clicked.connect(presenter.claim)
        self.statusBar().addPermanentWidget(self.queue_label)
        self.statusBar().addPermanentWidget(self.claim_button)
        self.statusBar().addPermanentWidget(self.progress)
        self.statusBar().addPermanentWidget(self.feed_label)
        self.statusBar().showMessage(f"Signed in as {user}.")

        QShortcut(QKeySequence("Escape"), self, presenter.stop)  # STOP from anywhere
        QShortcut(QKeySequence("Ctrl+Q"), self, self.close)  # sign out and quit
        self._bind()
        self.show_files()
        self.show_busy("")

    # --- layout --------------------------------------------------------------------------

    def _header(self, user: str, server: str, role: str) -> QFrame:
        header = QFrame()
        header.setObjectName("header")
        layout = QHBoxLayout(header)
        layout.setContentsMargins(14, 4, 6, 4)
        titles = QVBoxLayout()
        titles.setSpacing(0)
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
        layout.addSpacing(14)
        self.link_pill = QLabel()
        self.link_pill.setObjectName("pill")
        self.link_pill.setAccessibleName("Robot link status")
        layout.addWidget(self.link_pill)
        layout.addSpacing(14)
        self.stop_button = QPushButton("STOP")
        self.stop_button.setObjectName("stop")
        self.stop_button.setToolTip("Stop the robot now (Esc). Always available.")
        self.stop_button.setAccessibleName("Stop the robot")
        self.stop_button.setMinimumSize(170, 50)
        self.stop_button.setCursor(Qt.CursorShape.PointingHandCursor)
        layout.addWidget(self.stop_button)
        self.show_link(None, "")
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
        label = QLabel(  # Alt+P / Alt+O reach the Choose… buttons from the keyboard
            f"&Program ({kind.value}):" if kind is FileKind.PROGRAM else f"P&oints ({kind.value}):"
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
        layout.setSpacing(4)
        grid = QGridLayout()
        grid.setColumnStretch(1, 1)
        self.source_box = RefreshingCombo(self.presenter.refresh_workspaces)
        self.source_box.setAccessibleName("Load from files or from a workspace")
        self.source_box.setToolTip("Files on this computer, or a workspace you wrote in the IDE")
        self.source_box.addItem(FILES_SOURCE, None)
        source_label = QLabel("&From:")
        source_label.setBuddy(self.source_box)
        grid.addWidget(source_label, 0, 0)
        grid.addWidget(self.source_box, 0, 1, 1, 2)
        self.program_edit, self.program_button = self._file_row(grid, 1, FileKind.PROGRAM)
        self.points_edit, self.points_button = self._file_row(grid, 2, FileKind.POINTS)
        layout.addLayout(grid)

        buttons = QHBoxLayout()
        self.check_button = QPushButton("Chec&k")
        self.check_button.setToolTip("Check the program against the points (sends nothing)")
        self.load_button = QPushButton("&Load into robot")
        self.load_button.setObjectName("primary")
        self.load_button.setToolTip("Check, then load the program and its points into the robot")
        self.run_button = QPushButton("▶  &Run program")
        self.run_button.setObjectName("primary")
        self.run_button.setToolTip("Run the program loaded into the robot")
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
        self.exec_button = QPushButton("Se&nd")
        self.exec_button.setObjectName("primary")
        label = QLabel("&Instruction:")  # Alt+I
        label.setBuddy(self.exec_edit)
        layout.addWidget(label)
        layout.addWidget(self.exec_edit, 1)
        layout.addWidget(self.exec_button)
        return box

    def _robot_box(self) -> QGroupBox:
        box = QGroupBox("Robot")
        grid = QGridLayout(box)
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

        def caption(text: str) -> QLabel:
            label = QLabel(text)
            label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            return label

        grid.addWidget(caption("Now:"), 0, 0)
        grid.addWidget(v["activity"], 0, 1, 1, 3)
        grid.addWidget(caption("Servo:"), 1, 0)
        grid.addWidget(v["servo"], 1, 1)
        grid.addWidget(caption("Speed:"), 1, 2)
        grid.addWidget(v["override"], 1, 3)
        grid.addWidget(caption("Control:"), 2, 0)
        grid.addWidget(v["lease"], 2, 1, 1, 3)
        grid.addWidget(caption("Alarm:"), 3, 0)
        alarm_row = QHBoxLayout()
        alarm_row.addWidget(v["alarm"], 1)
        self.alarm_fix_button = QPushButton("Reset alarm")
        self.alarm_fix_button.setObjectName("fix")
        self.alarm_fix_button.setVisible(False)
        alarm_row.addWidget(self.alarm_fix_button)
        grid.addLayout(alarm_row, 3, 1, 1, 3)
        return box

    def _control_box(self) -> QGroupBox:
        """Servo, speed override and the hold-to-move jog pad."""
        box = QGroupBox("Servo, speed and jog")
        layout = QVBoxLayout(box)
        layout.setSpacing(4)
        row = QHBoxLayout()
        self.servo_on_button = QPushButton("Servo on")
        self.servo_off_button = QPushButton("Servo off")
        row.addWidget(QLabel("Servo:"))
        row.addWidget(self.servo_on_button)
        row.addWidget(self.servo_off_button)
        row.addSpacing(16)
        self.override_spin = QSpinBox()
        self.override_spin.setRange(OVERRIDE_PERCENT.start, OVERRIDE_PERCENT[-1])
        self.override_spin.setValue(30)
        self.override_spin.setSuffix(" %")
        self.override_spin.setAccessibleName("Speed override")
        self.override_button = QPushButton("Set speed")
        row.addWidget(QLabel("Speed:"))
        row.addWidget(self.override_spin)
        row.addWidget(self.override_button)
        row.addStretch(1)
        layout.addLayout(row)
        p = self.presenter
        self.jog_pad = JogPad(p.jog_press, p.jog_release, p.jog)
        layout.addWidget(self.jog_pad)
        return box

    def _log_box(self) -> QGroupBox:
        box = QGroupBox("Activity of this session")
        layout = QVBoxLayout(box)
        layout.setContentsMargins(6, 4, 6, 4)
        self.log = QPlainTextEdit()
        self.log.setReadOnly(True)
        self.log.setMaximumBlockCount(LOG_LINES)
        self.log.setAccessibleName("Activity log: time, action, result")
        self.log.setFixedHeight(96)
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
        # Running: show the program, where the running line is marked.
        self.run_button.clicked.connect(lambda: self.tabs.setCurrentWidget(self.program_view))
        self.alarm_fix_button.clicked.connect(self._fix_alarm)
        self.source_box.currentIndexChanged.connect(self._source_chosen)
        self.exec_button.clicked.connect(self._send_exec)
        self.exec_edit.returnPressed.connect(self._send_exec)
        self.servo_on_button.clicked.connect(lambda: p.servo(True))
        self.servo_off_button.clicked.connect(lambda: p.servo(False))
        self.override_button.clicked.connect(lambda: p.set_override(self.override_spin.value()))
        self.installEventFilter(self.jog_pad)  # a deactivated window stops the jog
        p.attach(self)

    def _fix_alarm(self) -> None:
        state = self.presenter.live.state
        if state is not None and state.alarm is not None and state.alarm.fix is not None:
            self.presenter.apply_fix(state.alarm.fix)

    def choose(self, kind: FileKind) -> None:
        title = "Choose a program" if kind is FileKind.PROGRAM else "Choose a points file"
        path = self.dialogs.open_file(title, FILE_FILTERS[kind], self)
        if path is not None:
            self.presenter.choose(kind, path)

    def _send_exec(self) -> None:
        if self.presenter.exec_statement(self.exec_edit.text()):
            self.exec_edit.selectAll()

    def show_notice(self, notice: Notice, on_fix: Callable[[], object] | None = None) -> None:
        self.dialogs.show(notice, self, on_fix)

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
            lines = len(chosen.text.splitlines())
            edit.setText(f"{chosen.name}  ·  {count(lines, 'line')}")
            edit.setCursorPosition(0)
            # The whole path on hover, never clipped.
            edit.setToolTip(str(chosen.path) if chosen.workspace is None else chosen.name)
            if view.toPlainText() != chosen.text:
                view.setPlainText(chosen.text)
                self.tabs.setCurrentWidget(view)  # show what was just chosen
        self.show_busy(p.busy)

    def show_workspaces(self, workspaces: tuple[WorkspaceInfo, ...]) -> None:
        box = self.source_box
        chosen = box.currentData()
        box.blockSignals(True)  # a new list is not a new choice
        box.clear()
        box.addItem(FILES_SOURCE, None)
        for workspace in workspaces:
            shared = " (shared)" if workspace.shared else ""
            box.addItem(f"Workspace: {workspace.name}{shared}", workspace.id)
        box.setCurrentIndex(max(0, box.findData(chosen)) if chosen is not None else 0)
        box.blockSignals(False)

    def _source_chosen(self) -> None:
        data = self.source_box.currentData()
        self.presenter.choose_workspace(int(data) if data is not None else None)
        self.show_busy(self.presenter.busy)

    def show_busy(self, what: str) -> None:
        idle = not what
        has_program = self.presenter.program is not None
        for button in (
            self.run_button,
            self.exec_button,
            self.alarm_fix_button,
            self.servo_on_button,
            self.servo_off_button,
            self.override_button,
        ):
            button.setEnabled(idle)
        self.jog_pad.set_buttons_enabled(idle)
        # Choosing a file is local: allowed while a command runs (it uses its own copy).
        from_files = self.source_box.currentData() is None
        self.program_button.setEnabled(from_files)
        self.points_button.setEnabled(from_files)
        self.source_box.setEnabled(idle)
        self.check_button.setEnabled(idle and has_program)
        self.load_button.setEnabled(idle and has_program)
        self.stop_button.setEnabled(True)  # never disabled
        bar = self.statusBar()
        if what:
            self._busy_text = f"{what}…"
            bar.showMessage(self._busy_text)
        elif bar.currentMessage() == self._busy_text:
            bar.clearMessage()  # done, and nothing said about it: never a stale "…ing"

    def show_progress(self, percent: int | None) -> None:
        self.progress.setVisible(percent is not None)
        if percent is not None:
            self.progress.setValue(percent)

    def show_jog(self, held: JogKey | None) -> None:
        for (slot, direction), button in self.jog_pad.buttons.items():
            down = held is not None and (
                self.jog_pad.axis_of(slot) == held.axis and direction == held.direction
            )
            set_level(button, "held" if down else "")
            button.setDown(down)
        if held is not None:
            self.statusBar().showMessage(
                f"Jogging {jog_label(held.frame, held.axis, held.direction)}: let go to stop."
            )

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
            else f"Check results: {count(errors, 'error')}, "
            f"{count(total - errors, 'warning or note')}"
        )

    def show_link(self, status: LinkStatus | None, detail: str) -> None:
        self.link_pill.setText(link_words(status))
        self.link_pill.setToolTip(detail or link_words(status))
        set_level(self.link_pill, LINK_LEVEL[status])

    def show_feed(self, status: FeedStatus, detail: str) -> None:
        self.feed_label.setText(FEED_WORDS[status])
        self.feed_label.setToolTip(detail)

    def show_state(self, state: StateOut) -> None:
        self.position.show_state(state)
        v = self.status_values
        loaded = self.presenter.loaded
        v["activity"].setText(activity_text(state, loaded))
        set_level(v["activity"], ACTIVITY_LEVEL.get(state.activity, "busy"))
        v["servo"].setText(on_off(state.servo))
        v["override"].setText("—" if state.override is None else f"{state.override} %")
        if state.override is not None and not self.override_spin.hasFocus():
            self.override_spin.setValue(state.override)  # what the robot has, until edited
        v["lease"].setText(control_text(state, self.presenter.me))
        alarm = state.alarm
        v["alarm"].setText(alarm_said(alarm) if alarm else "None")
        v["alarm"].setToolTip(alarm_said(alarm) if alarm else "")
        set_level(v["alarm"], "alarm" if alarm else "")
        fix = alarm.fix if alarm and alarm.fix in FIXES_OFFERED else None
        self.alarm_fix_button.setVisible(fix is not None)
        if fix is not None:
            self.alarm_fix_button.setText(FIX_LABELS[fix])
        self._mark_line(state)

    def _mark_line(self, state: StateOut) -> None:
        """Highlight the running (or paused) line in the program, when it is the loaded file,
        and scroll it into view when it changes (a long program's line is followed)."""
        p = self.presenter
        shows = state.activity in (Activity.RUNNING, Activity.PAUSED) or bool(
            state.running and state.line
        )
        line = file_line(state.line, p.loaded) if shows else None
        same_file = p.loaded is not None and p.program is not None
        same_file = same_file and p.program.path.name == p.loaded.name  # type: ignore[union-attr]
        selections: list[QTextEdit.ExtraSelection] = []
        if line is not None and same_file:
            block = self.program_view.document().findBlockByNumber(line - 1)
            if block.isValid():
                mark = QTextEdit.ExtraSelection()
                mark.format.setBackground(QColor("#fff59d"))
                mark.format.setProperty(QTextFormat.Property.FullWidthSelection, True)
                mark.cursor = QTextCursor(block)
                selections.append(mark)
                if line != self._followed_line:
                    self.program_view.setTextCursor(QTextCursor(block))
                    self.program_view.ensureCursorVisible()
        self._followed_line = line if selections else None
        self.program_view.setExtraSelections(selections)

    def append_log(self, line: str) -> None:
        self.log.appendPlainText(line)

    def show_status(self, text: str) -> None:
        self.statusBar().showMessage(text)

    def show_queue(self, line: str, offered: bool) -> None:
        """The lab robot's queue; when the arm is offered to this user, a claim button that
        cannot be missed (the window comes to the front and asks for attention)."""
        self.queue_label.setText(line)
        was = self.claim_button.isVisible()
        self.claim_button.setVisible(offered)
        if offered and not was:
            self.raise_()
            self.activateWindow()
            QApplication.alert(self)

    def closeEvent(self, event: QCloseEvent) -> None:  # noqa: N802 (Qt's name)
        self.presenter.shutdown()
        super().closeEvent(event)
        if self.on_closed is not None:
            self.on_closed()


__all__ = ["MainWindow"]
