"""The main window: files, instruction and activity log on the left; the robot's state, the
servo, speed and jog pad, and the live position on the right; a STOP button that is always
there and always enabled. Laid out to fit a 1366×700 laptop screen without scrolling.

Widgets only: every action goes to the `Presenter`, every dialog through `Dialogs`. The
window lays the panels out, wires them to the presenter and is its `View`; the panels that
show most are their own modules (`program_box`, `robot_box`, `position`, `jogpad`).
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import Qt
from PySide6.QtGui import QCloseEvent, QKeySequence, QShortcut
from PySide6.QtWidgets import (
    QApplication,
    QComboBox,
    QFrame,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMainWindow,
    QPlainTextEdit,
    QProgressBar,
    QPushButton,
    QSizePolicy,
    QSpinBox,
    QVBoxLayout,
    QWidget,
)

from melfa.desktop.api import PRIVATE_TARGET, TARGET_LABELS, CheckResult, WorkspaceInfo
from melfa.desktop.dialogs import Dialogs, Notice
from melfa.desktop.files import FileKind
from melfa.desktop.hold import JogKey
from melfa.desktop.jogpad import JogPad
from melfa.desktop.live import FeedStatus
from melfa.desktop.messages import offered_fix
from melfa.desktop.position import PositionBox
from melfa.desktop.presenter import Presenter
from melfa.desktop.program_box import ProgramBox
from melfa.desktop.robot_box import RobotBox
from melfa.desktop.style import LINK_LEVEL, STYLE, set_level
from melfa.desktop.words import jog_label, link_words
from melfa.live.messages import StateOut
from melfa.protocol import OVERRIDE_PERCENT
from melfa.vocab.ide import IDE_WORDS
from melfa.vocab.link import LinkStatus
from melfa.vocab.queue import QUEUE_WORDS
from melfa.vocab.roles import role_words

FILE_FILTERS = {
    FileKind.PROGRAM: "MELFA BASIC IV programs (*.MB4 *.mb4);;All files (*)",
    FileKind.POINTS: "Points files (*.POS *.pos);;All files (*)",
}
LOG_LINES = 500
FEED_WORDS = {
    FeedStatus.CONNECTING: "Live updates: connecting…",
    FeedStatus.CONNECTED: "Live updates: on",
    FeedStatus.DISCONNECTED: "Live updates: reconnecting…",
    FeedStatus.REFUSED: "Live updates: refused (sign in again)",
    FeedStatus.CLOSED: "Live updates: off",
}


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
        role = role_words(client.user.role) if client.user else ""
        root.addWidget(self._header(user, client.server, role))

        body = QHBoxLayout()
        body.setSpacing(10)
        left = QVBoxLayout()
        left.setSpacing(4)
        self.program_box = ProgramBox(presenter.refresh_workspaces)
        left.addWidget(self.program_box, 1)
        left.addWidget(self._exec_box())
        left.addWidget(self._log_box())
        right = QVBoxLayout()
        right.setSpacing(4)
        self.robot_box = RobotBox()
        right.addWidget(self.robot_box)
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
        self.queue_label = QLabel("")
        self.queue_label.setAccessibleName(QUEUE_WORDS.title)
        self.claim_button = QPushButton(QUEUE_WORDS.claim)
        self.claim_button.setObjectName("claim")
        self.claim_button.setToolTip(QUEUE_WORDS.claim_hint)
        self.claim_button.setVisible(False)
        self.claim_button.clicked.connect(presenter.claim)
        self.statusBar().addPermanentWidget(self.queue_label)
        self.statusBar().addPermanentWidget(self.claim_button)
        self.statusBar().addPermanentWidget(self.progress)
        self.statusBar().addPermanentWidget(self.feed_label)
        self.statusBar().showMessage(IDE_WORDS["signed-in-as"].format(user=user, role=role))

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
        files = self.program_box
        files.program_button.clicked.connect(lambda: self.choose(FileKind.PROGRAM))
        files.points_button.clicked.connect(lambda: self.choose(FileKind.POINTS))
        files.check_button.clicked.connect(p.check)
        files.load_button.clicked.connect(p.load)
        files.run_button.clicked.connect(p.run)
        # Running: show the program, where the running line is marked.
        files.run_button.clicked.connect(lambda: files.tabs.setCurrentWidget(files.program_view))
        self.robot_box.alarm_fix_button.clicked.connect(self._fix_alarm)
        files.source_box.currentIndexChanged.connect(self._source_chosen)
        self.exec_button.clicked.connect(self._send_exec)
        self.exec_edit.returnPressed.connect(self._send_exec)
        self.servo_on_button.clicked.connect(lambda: p.servo(True))
        self.servo_off_button.clicked.connect(lambda: p.servo(False))
        self.override_button.clicked.connect(lambda: p.set_override(self.override_spin.value()))
        self.installEventFilter(self.jog_pad)  # a deactivated window stops the jog
        p.attach(self)

    def _fix_alarm(self) -> None:
        state = self.presenter.live.state
        fix = offered_fix(state.alarm.fix) if state is not None and state.alarm else None
        if fix is not None:
            self.presenter.apply_fix(fix)

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
        self.program_box.show_files(p.program, p.points)
        self.show_busy(p.busy)

    def show_workspaces(self, workspaces: tuple[WorkspaceInfo, ...]) -> None:
        self.program_box.show_workspaces(workspaces)

    def _source_chosen(self) -> None:
        data = self.program_box.source_box.currentData()
        self.presenter.choose_workspace(int(data) if data is not None else None)
        self.show_busy(self.presenter.busy)

    def show_busy(self, what: str) -> None:
        idle = not what
        self.program_box.show_busy(idle, self.presenter.program is not None)
        for button in (
            self.exec_button,
            self.robot_box.alarm_fix_button,
            self.servo_on_button,
            self.servo_off_button,
            self.override_button,
        ):
            button.setEnabled(idle)
        self.jog_pad.set_buttons_enabled(idle)
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
        self.program_box.show_check(result)

    def show_link(self, status: LinkStatus | None, detail: str) -> None:
        self.link_pill.setText(link_words(status))
        self.link_pill.setToolTip(detail or link_words(status))
        set_level(self.link_pill, LINK_LEVEL[status])

    def show_feed(self, status: FeedStatus, detail: str) -> None:
        self.feed_label.setText(FEED_WORDS[status])
        self.feed_label.setToolTip(detail)

    def show_state(self, state: StateOut) -> None:
        p = self.presenter
        self.position.show_state(state)
        self.robot_box.show_state(state, p.loaded, p.me, p.live.queued)
        if state.override is not None and not self.override_spin.hasFocus():
            self.override_spin.setValue(state.override)  # what the robot has, until edited
        self.program_box.mark_line(state, p.loaded, p.program)

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
