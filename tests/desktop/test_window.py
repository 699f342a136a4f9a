"""The window offscreen against a served virtual robot: sign-in, refusals with dialogs and
their one-click fixes, load and run reaching the controller (the running line of the file),
live pose, servo, speed, hold-to-move jog by button and key, STOP, and the log's words.
tests/desktop/test_xcb.py does the same on a real X display with real key events."""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

os.environ["QT_QPA_PLATFORM"] = "offscreen"  # before Qt starts: no display needed
pytest.importorskip("PySide6.QtWidgets", reason="the desktop extra (PySide6) is not installed")

from PySide6.QtCore import QEvent, Qt
from PySide6.QtGui import QFocusEvent, QKeyEvent
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication, QMessageBox, QWidget

from melfa.desktop.api import ApiClient
from melfa.desktop.app import application
from melfa.desktop.dialogs import Notice, NoticeKind, QtDialogs
from melfa.desktop.files import FileKind
from melfa.desktop.live import FeedStatus
from melfa.desktop.login import LoginDialog
from melfa.desktop.messages import LiveMessage, parse_message
from melfa.desktop.presenter import Presenter
from melfa.desktop.window import MainWindow
from melfa.vocab.activity import Activity
from melfa.vocab.jog import JogEnd
from melfa.vocab.link import LinkStatus
from tests.desktop.conftest import EXAMPLES, Server

LOOP_PROGRAM = """10 SERVO ON
20 OVRD 20
30 *LOOP
40 MOV Pa
50 MOV Pb
60 GOTO *LOOP
"""
NUMBERED_PROGRAM = "5 SERVO ON\n7 OVRD 20\n100 MOV Pa\n230 MOV Pb\n999 END\n"
"""Numbered by the student, not in tens: the window must map steps through the real text."""
FAULTY_PROGRAM = "10 SERVO ON\n20 MOV Pa\n30 FOO 1\n40 MOVE Pb\n"
LONG_PROGRAM = (
    "10 SERVO ON\n20 OVRD 20\n"
    + "".join(f"{30 + 10 * n} M1 = {n}\n" for n in range(80))
    + "900 *LOOP\n910 MOV Pa\n920 MOV Pb\n930 GOTO *LOOP\n"
)
"""Its moves at lines 84–85, far below what the program view shows at first."""


class RecordingDialogs:
    """The window's dialog hook for tests: records what the user would be told (and the
    fix offered with it) and answers file choosers from a queue, with no modal loop."""

    def __init__(self) -> None:
        self.notices: list[Notice] = []
        self.fixes: list[Callable[[], object] | None] = []
        self.files: list[Path] = []

    def show(
        self, notice: Notice, parent: QWidget | None, on_fix: Callable[[], object] | None = None
    ) -> None:
        self.notices.append(notice)
        self.fixes.append(on_fix)

    def open_file(self, title: str, filters: str, parent: QWidget | None) -> Path | None:
        return self.files.pop(0) if self.files else None


def wait_until(condition: Callable[[], object], timeout: float = 20.0) -> None:
    """Run the Qt event loop until ``condition()`` holds (a generous bound, not a timing test)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError("condition not met in time")
        QApplication.processEvents()
        time.sleep(0.01)


@pytest.fixture(scope="module")
def qapp() -> QApplication:
    return application()


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("desktop-files")
    shutil.copy(EXAMPLES / "sample.MB4", folder / "sample.MB4")
    shutil.copy(EXAMPLES / "sample.POS", folder / "sample.POS")
    (folder / "loop.mb4").write_text(LOOP_PROGRAM)
    (folder / "numbered.MB4").write_text(NUMBERED_PROGRAM)
    (folder / "faulty.MB4").write_text(FAULTY_PROGRAM)
    (folder / "notes.txt").write_text("10 END\n")
    (folder / "long.MB4").write_text(LONG_PROGRAM)
    return folder


@dataclass
class Ui:
    window: MainWindow
    presenter: Presenter
    dialogs: RecordingDialogs

    def take_notices(self) -> list[Notice]:
        out, self.dialogs.notices, self.dialogs.fixes = self.dialogs.notices, [], []
        return out

    def choose(self, kind: FileKind, path: Path) -> None:
        """Click "Choose…" and pick ``path`` in the (recorded) file dialog."""
        self.dialogs.files.append(path)
        files = self.window.program_box
        button = files.program_button if kind is FileKind.PROGRAM else files.points_button
        button.click()

    def idle(self) -> None:
        wait_until(lambda: not self.presenter.busy, timeout=60)


def log_text(ui: Ui) -> str:
    return ui.window.log.toPlainText()


def sign_in(server: Server, password: str) -> LoginDialog:
    dialog = LoginDialog(server.url, "admin")
    dialog.password_edit.setText(password)
    dialog.sign_in_button.click()
    return dialog


@pytest.fixture(scope="module")
def ui(qapp: QApplication, server: Server) -> Iterator[Ui]:
    dialog = sign_in(server, server.password)
    assert dialog.client is not None, dialog.error_label.text()
    dialogs = RecordingDialogs()
    presenter = Presenter(dialog.client)
    window = MainWindow(presenter, dialogs)
    window.show()
    presenter.start()
    wait_until(
        lambda: (
            presenter.live.state is not None and presenter.live.feed_status is FeedStatus.CONNECTED
        )
    )
    wait_until(lambda: not presenter.busy)  # the first state read done: buttons enabled
    yield Ui(window, presenter, dialogs)
    window.close()
    assert presenter.closed


@pytest.fixture(scope="module")
def observer(server: Server) -> ApiClient:
    """A second session that only reads the state: proof that commands reached the robot."""
    client = ApiClient(server.url)
    client.login("admin", server.password)
    return client


def test_sign_in_accepts_the_right_password(qapp: QApplication, server: Server) -> None:
    dialog = sign_in(server, server.password)
    assert dialog.result() == LoginDialog.DialogCode.Accepted
    assert dialog.client is not None and dialog.client.signed_in
    assert dialog.user is not None and dialog.user.username == "admin"
    dialog.client.logout()


def test_wrong_password_is_shown_in_the_dialog(qapp: QApplication, server: Server) -> None:
    dialog = sign_in(server, "wrong-password")
    assert dialog.client is None
    assert dialog.result() != LoginDialog.DialogCode.Accepted
    assert dialog.error_label.text() == "Wrong username or password."
    assert dialog.password_edit.text() == ""  # cleared for the retry


def test_window_shows_link_and_live_pose(ui: Ui) -> None:
    assert ui.window.link_pill.text() == "Robot connected"
    assert ui.presenter.live.link is LinkStatus.CONNECTED
    state = ui.presenter.live.state
    assert state is not None and state.pose is not None
    assert ui.window.pose_values[0].text() == f"{state.pose[0]:.2f}".replace(",", " ")
    assert ui.window.stop_button.isEnabled()


def test_wrong_extensions_are_refused_with_a_dialog(ui: Ui, files: Path) -> None:
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "notes.txt")
    ui.choose(FileKind.POINTS, files / "sample.MB4")
    program, points = ui.take_notices()
    assert (program.kind, program.title) == (NoticeKind.ERROR, "Wrong extension")
    assert program.text == "notes.txt: wrong extension (.txt): choose a .MB4 program."
    assert points.title == "Wrong extension"
    assert "choose a .POS points file" in points.text
    assert ui.presenter.program is None or ui.presenter.program.path.name != "notes.txt"
    assert "notes.txt" not in ui.window.program_box.program_edit.text()
    assert "sample.MB4" not in ui.window.program_box.points_edit.text()


def test_faulty_program_is_refused_with_its_diagnostics(
    ui: Ui, files: Path, observer: ApiClient
) -> None:
    before = observer.state().seq
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "faulty.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    assert ui.window.program_box.load_button.isEnabled()
    ui.window.program_box.load_button.click()
    ui.idle()
    [notice] = ui.take_notices()
    assert (notice.kind, notice.title) == (NoticeKind.ERROR, "Program has errors")
    assert notice.text == "faulty.MB4 has 2 errors; nothing was sent to the robot."
    assert notice.lines[0].startswith("3:4  ") and "FOO" in notice.lines[0]
    assert notice.lines[1].startswith("4:4  ")
    assert "3:4  " in notice.listing
    # the check panel lists the same findings
    rows = [
        ui.window.program_box.diagnostics.topLevelItem(i)
        for i in range(ui.window.program_box.diagnostics.topLevelItemCount())
    ]
    assert [(r.text(0), r.text(1)) for r in rows if r.text(1) == "error"] == [
        ("3:4", "error"),
        ("4:4", "error"),
    ]
    assert observer.state().seq >= before  # still served; nothing was uploaded (no busy upload)


def test_load_and_run_reach_the_virtual_controller(
    ui: Ui, files: Path, observer: ApiClient
) -> None:
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "numbered.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    assert ui.window.program_box.program_edit.text() == "numbered.MB4  ·  5 lines"
    shown = ui.window.program_box.program_edit.toolTip()
    assert shown == str(files / "numbered.MB4")  # the whole path
    ui.presenter.last_upload = None
    ui.window.program_box.load_button.click()
    ui.idle()
    assert ui.take_notices() == []
    assert ui.presenter.last_upload is not None
    assert "Loaded numbered.MB4 and sample.POS into the robot (5 lines" in log_text(ui)

    start_joints = observer.state().joints
    ui.window.program_box.run_button.click()
    ui.idle()
    assert ui.take_notices() == []

    # The server (asked by another session) sees the program run and the arm move...
    wait_until(lambda: observer.state().running is True, timeout=30)
    wait_until(lambda: observer.state().joints != start_joints, timeout=30)
    # ...and the window shows, live from the WebSocket, the line of the student's file
    # (numbered 5, 7, 100, 230, 999: step 230 is line 4, not "line 23" or "step 230"),
    # highlighted in the program as it runs.
    now = ui.window.robot_box.status_values["activity"]
    wait_until(lambda: now.text() == "Running line 4 of numbered.MB4", timeout=60)
    [mark] = ui.window.program_box.program_view.extraSelections()
    assert mark.cursor.block().text() == "230 MOV Pb"
    wait_until(
        lambda: ui.presenter.live.state is not None and ui.presenter.live.state.running is False
    )
    wait_until(
        lambda: ui.presenter.live.state is not None and ui.presenter.live.state.moving is False
    )
    final = ui.presenter.live.state
    assert final is not None and final.joints is not None and final.pose is not None
    wait_until(lambda: ui.window.joint_values[0].text() == f"{final.joints[0]:.2f}")
    wait_until(lambda: now.text() == "Idle")
    assert ui.window.program_box.program_view.extraSelections() == []
    assert ui.window.robot_box.status_values["servo"].text() == "On"
    assert "Run: numbered.MB4 started" in log_text(ui)


def test_exec_moves_the_arm_and_the_pose_updates(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: observer.state().moving is False and observer.state().running is False)
    still = observer.state().pose
    assert still is not None
    z_before = still[2]
    ui.window.exec_edit.setText("MOV P_CURR+(0,0,-30,0,0,0)")
    ui.window.exec_button.click()
    ui.idle()
    assert ui.take_notices() == []

    def lowered() -> bool:
        now = ui.presenter.live.state
        return now is not None and now.pose is not None and now.pose[2] < z_before - 25

    wait_until(lowered, timeout=30)
    wait_until(lambda: ui.presenter.live.state is not None and not ui.presenter.live.state.moving)
    now = ui.presenter.live.state
    assert now is not None and now.pose is not None
    wait_until(lambda: ui.window.pose_values[2].text() == f"{now.pose[2]:.2f}")
    observed = observer.state().pose
    assert observed is not None and abs(observed[2] - (z_before - 30)) < 0.5


def still(observer: ApiClient) -> bool:
    state = observer.state()
    idle = state.activity in (Activity.IDLE, Activity.PAUSED, Activity.AT)  # not moving
    return state.moving is False and state.running is False and not state.jogging and idle


def x_of(observer: ApiClient) -> float:
    pose = observer.state().pose
    assert pose is not None
    return pose[0]


def stays_put(ui: Ui, observer: ApiClient) -> None:
    """After a release: no jog, no motion, and the pose unchanged over fresh snapshots (to
    0.2 mm: a pose computed from the joints and the controller's rounded one differ by
    ~0.06 mm; a jog at even 1 % moves far more between snapshots). Snapshots taken after
    the release first: one from before it may not show the arm moving yet."""
    seq = observer.state().seq
    wait_until(lambda: observer.state().seq >= seq + 5 and still(observer), timeout=30)
    pose = observer.state().pose
    seq = observer.state().seq
    wait_until(lambda: observer.state().seq >= seq + 5, timeout=30)
    now = observer.state().pose
    assert pose is not None and now is not None
    assert max(abs(a - b) for a, b in zip(pose, now, strict=True)) < 0.2, (pose, now)


def test_servo_and_speed_controls(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    ui.window.servo_off_button.click()
    ui.idle()
    wait_until(lambda: observer.state().servo is False)
    wait_until(lambda: ui.window.robot_box.status_values["servo"].text() == "Off")
    ui.window.override_spin.setValue(25)
    ui.window.override_button.click()
    ui.idle()
    wait_until(lambda: observer.state().override == 25)
    wait_until(lambda: ui.window.robot_box.status_values["override"].text() == "25 %")
    assert "Servo off" in log_text(ui) and "Speed override: 25 %" in log_text(ui)


def test_a_held_jog_button_moves_only_while_held(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    pad = ui.window.jog_pad
    button = pad.buttons[(0, 1)]
    assert button.text() == "X+   W"
    before = x_of(observer)
    QTest.mousePress(button, Qt.MouseButton.LeftButton)  # asking to move: servo on, audited
    try:
        wait_until(lambda: observer.state().jogging, timeout=30)
        wait_until(lambda: x_of(observer) > before + 2, timeout=30)
        now = ui.window.robot_box.status_values["activity"]
        wait_until(lambda: now.text() == "Jogging X+ (base)")  # the window, live
        assert ui.presenter.live.hold.active
    finally:
        QTest.mouseRelease(button, Qt.MouseButton.LeftButton)
    assert not ui.presenter.live.hold.active
    stays_put(ui, observer)
    assert ui.take_notices() == []
    assert observer.state().servo is True
    assert "Jog X+ (held)" in log_text(ui)


def test_a_held_key_jogs_and_its_auto_repeat_is_ignored(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    pad = ui.window.jog_pad
    before = x_of(observer)
    QTest.keyPress(pad, Qt.Key.Key_S)  # S: X−
    start_id = ui.presenter.live.hold.start_id
    assert start_id is not None
    try:
        wait_until(lambda: x_of(observer) < before - 2, timeout=30)
        # The keyboard's auto-repeat sends release+press pairs: one jog, never restarted.
        for _ in range(3):
            for kind in (QEvent.Type.KeyRelease, QEvent.Type.KeyPress):
                event = QKeyEvent(kind, Qt.Key.Key_S, Qt.KeyboardModifier.NoModifier, "s", True)
                QApplication.sendEvent(pad, event)
        assert ui.presenter.live.hold.active and ui.presenter.live.hold.start_id == start_id
        assert observer.state().jogging
    finally:
        QTest.keyRelease(pad, Qt.Key.Key_S)
    wait_until(lambda: not ui.presenter.live.hold.active, timeout=5)
    stays_put(ui, observer)


def test_the_status_bar_says_the_jog_stopped_once_the_key_is_let_go(
    ui: Ui, observer: ApiClient
) -> None:
    """While D is held it says how to stop; once let go, what is true then (it went on
    saying "let go to stop" after the arm had stopped)."""
    wait_until(lambda: still(observer))
    pad, bar = ui.window.jog_pad, ui.window.statusBar()
    QTest.keyPress(pad, Qt.Key.Key_D)  # D: Y-
    try:
        wait_until(lambda: observer.state().jogging, timeout=30)
        held = bar.currentMessage()
        assert held.startswith("Jogging Y") and held.endswith("let go to stop."), held
    finally:
        QTest.keyRelease(pad, Qt.Key.Key_D)
    wait_until(lambda: not ui.presenter.live.hold.active, timeout=5)
    assert bar.currentMessage() == f"Jog stopped: {JogEnd.RELEASED.words()}."
    stays_put(ui, observer)
    assert bar.currentMessage() == f"Jog stopped: {JogEnd.RELEASED.words()}."


def test_x_auto_repeat_not_marked_as_repeat_is_still_one_jog(ui: Ui, observer: ApiClient) -> None:
    """X sends a held key's repeats as a key-up and a key-down at once, and Qt's xcb does
    not always mark them as repeats: each pair must not end the jog and start another."""
    ui.take_notices()
    wait_until(lambda: still(observer))
    pad = ui.window.jog_pad
    jogs = log_text(ui).count("Jog X+ (held)")
    QTest.keyPress(pad, Qt.Key.Key_W)
    start_id = ui.presenter.live.hold.start_id
    assert start_id is not None
    try:
        wait_until(lambda: observer.state().jogging, timeout=30)
        for _ in range(5):
            for kind in (QEvent.Type.KeyRelease, QEvent.Type.KeyPress):
                event = QKeyEvent(kind, Qt.Key.Key_W, Qt.KeyboardModifier.NoModifier, "w")
                QApplication.sendEvent(pad, event)
            QApplication.processEvents()
        assert ui.presenter.live.hold.active and ui.presenter.live.hold.start_id == start_id
        assert pad.buttons[(0, 1)].isDown()
    finally:
        QTest.keyRelease(pad, Qt.Key.Key_W)
    wait_until(lambda: not ui.presenter.live.hold.active, timeout=5)  # a real let-go stops it
    assert not pad.buttons[(0, 1)].isDown()
    stays_put(ui, observer)
    assert log_text(ui).count("Jog X+ (held)") == jogs + 1


def test_losing_the_keyboard_stops_a_held_jog(ui: Ui, observer: ApiClient) -> None:
    wait_until(lambda: still(observer))
    pad = ui.window.jog_pad
    QTest.keyPress(pad, Qt.Key.Key_A)  # A: Y+
    wait_until(lambda: observer.state().jogging, timeout=30)
    pad.frame_box.setCurrentIndex(1)  # a changed frame lets go of the held key
    assert not ui.presenter.live.hold.active
    stays_put(ui, observer)
    QTest.keyRelease(pad, Qt.Key.Key_A)
    pad.frame_box.setCurrentIndex(0)
    QTest.keyPress(pad, Qt.Key.Key_A)
    wait_until(lambda: observer.state().jogging, timeout=30)
    pad.focusOutEvent(QFocusEvent(QEvent.Type.FocusOut))  # the keyboard went elsewhere
    assert not ui.presenter.live.hold.active
    stays_put(ui, observer)
    QTest.keyRelease(pad, Qt.Key.Key_A)


def test_one_step_mode_and_frame_labels(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    pad = ui.window.jog_pad
    pad.step_box.setChecked(True)
    try:
        before = x_of(observer)
        QTest.mouseClick(pad.buttons[(0, 1)], Qt.MouseButton.LeftButton)
        ui.idle()
        assert ui.take_notices() == []
        wait_until(lambda: x_of(observer) > before + 0.5, timeout=30)
        stays_put(ui, observer)
        assert "Jog step X+: done" in log_text(ui)
    finally:
        pad.step_box.setChecked(False)
    pad.frame_box.setCurrentIndex(2)
    assert pad.buttons[(2, -1)].text() == "J3−   ↓"
    pad.group_box.setCurrentIndex(1)
    assert pad.buttons[(2, -1)].text() == "J6−   ↓"
    pad.frame_box.setCurrentIndex(0)
    assert pad.buttons[(2, -1)].text() == "Z−   ↓"


def test_servo_off_offers_turn_on_and_retry(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    ui.window.servo_off_button.click()
    ui.idle()
    wait_until(lambda: observer.state().servo is False)
    pose = observer.state().pose
    assert pose is not None
    ui.window.exec_edit.setText("MOV P_CURR+(0,0,-10,0,0,0)")
    ui.window.exec_button.click()
    ui.idle()
    [notice] = ui.dialogs.notices
    [on_fix] = ui.dialogs.fixes
    assert notice.title == "Instruction refused"
    assert "The servo is off" in notice.text and "(code L2000)" in notice.text
    assert notice.fix_label == "Turn on and retry"
    assert on_fix is not None
    ui.take_notices()
    on_fix()  # the student clicks "Turn on and retry"
    ui.idle()
    wait_until(lambda: observer.state().servo is True)
    wait_until(lambda: not ui.presenter.busy and "Instruction MOV" in log_text(ui), timeout=30)
    wait_until(lambda: still(observer), timeout=30)
    now = observer.state().pose
    assert now is not None and abs(now[2] - (pose[2] - 10)) < 0.5
    assert ui.take_notices() == []


def test_a_refused_instruction_says_why_and_offers_the_fix(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    ui.window.exec_edit.setText("MOV P_NOWHERE_AT_ALL")
    ui.window.exec_button.click()
    ui.idle()
    [notice] = ui.take_notices()
    assert notice.title == "Instruction refused"
    assert "before it has a value" in notice.text and "(code L3700)" in notice.text
    assert "1;1;" not in notice.text  # never the wire request
    alarm = ui.window.robot_box.status_values["alarm"]
    wait_until(lambda: alarm.text().startswith("L3700 "))
    assert ui.window.robot_box.alarm_fix_button.isVisible()
    assert ui.window.robot_box.alarm_fix_button.text() == "Reset alarm"
    wait_until(lambda: ui.window.robot_box.status_values["activity"].text() == "Alarm L3700")
    ui.window.robot_box.alarm_fix_button.click()
    ui.idle()
    assert ui.take_notices() == []
    wait_until(lambda: alarm.text() == "None")
    assert not ui.window.robot_box.alarm_fix_button.isVisible()


def test_stop_stops_a_running_program(ui: Ui, files: Path, observer: ApiClient) -> None:
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "loop.mb4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.window.program_box.load_button.click()
    ui.idle()
    assert ui.take_notices() == []
    ui.window.program_box.run_button.click()
    ui.idle()
    wait_until(lambda: observer.state().running is True, timeout=30)
    assert ui.window.stop_button.isEnabled()
    ui.window.stop_button.click()
    wait_until(lambda: observer.state().running is False, timeout=30)
    now = ui.window.robot_box.status_values["activity"]
    wait_until(lambda: now.text().startswith(("Paused at line", "Idle")))
    assert ui.take_notices() == []
    assert "STOP: the robot stopped" in log_text(ui)


def test_the_log_speaks_the_students_words(ui: Ui, files: Path, observer: ApiClient) -> None:
    """A load, a refusal and a servo switch, logged: no internal names, wire requests or
    Python text (and whatever else this session logged before)."""
    ui.take_notices()
    wait_until(lambda: still(observer))
    ui.choose(FileKind.PROGRAM, files / "sample.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.window.program_box.load_button.click()
    ui.idle()
    ui.window.exec_edit.setText("MOV P_NOT_THERE")
    ui.window.exec_button.click()
    ui.idle()
    wait_until(ui.window.robot_box.alarm_fix_button.isVisible)  # the alarm's fix: Reset alarm
    ui.window.robot_box.alarm_fix_button.click()
    ui.idle()
    ui.window.servo_on_button.click()
    ui.idle()
    text = log_text(ui)
    assert "Loaded sample.MB4 and sample.POS into the robot (7 lines" in text
    assert "Instruction refused: MOV P_NOT_THERE: The program uses a point" in text
    assert "(code L3700)" in text and "Servo on" in text
    for internal in ("load_project", "jog_step", "reset_alarm", "1;1;", "Traceback", "None"):
        assert internal not in text
    assert "(step " not in text and "slot 1" not in text and "items" not in text


def test_the_running_line_is_scrolled_into_view(ui: Ui, files: Path, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: still(observer))
    ui.choose(FileKind.PROGRAM, files / "long.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    view = ui.window.program_box.program_view
    assert view.firstVisibleBlock().blockNumber() == 0  # the top shows, the moves do not
    ui.window.program_box.load_button.click()
    ui.idle()
    ui.window.program_box.run_button.click()
    ui.idle()
    assert ui.take_notices() == []
    try:

        def marked_and_visible() -> bool:
            marks = view.extraSelections()
            if not marks or marks[0].cursor.block().text() not in ("910 MOV Pa", "920 MOV Pb"):
                return False
            block = marks[0].cursor.block()
            shown = view.blockBoundingGeometry(block).translated(view.contentOffset())
            return view.viewport().rect().contains(shown.toRect())

        wait_until(marked_and_visible, timeout=60)
        assert view.firstVisibleBlock().blockNumber() > 40
    finally:
        ui.presenter.stop()
        wait_until(lambda: observer.state().running is False, timeout=30)
        wait_until(lambda: still(observer), timeout=30)


def test_notices_keep_coming_after_one_is_closed(qapp: QApplication) -> None:
    """The real dialogs (offscreen): a notice closed with OK, then the next, and the next."""
    dialogs = QtDialogs()
    parent = QWidget()
    for n in range(3):
        dialogs.show(Notice(NoticeKind.ERROR, f"Load refused {n}", "Fix line 2."), parent)
        [box] = [b for b in dialogs.open_boxes if b.windowTitle() == f"Load refused {n}"]
        assert box.isVisible()
        box.button(QMessageBox.StandardButton.Ok).click()  # the student closes it
        QApplication.processEvents()
        QApplication.sendPostedEvents(None, QEvent.Type.DeferredDelete.value)  # deleted now
        assert dialogs.open_boxes == []


def test_stop_stays_enabled_while_busy(ui: Ui) -> None:
    ui.presenter._set_busy("Loading")
    try:
        files = ui.window.program_box
        assert not files.load_button.isEnabled() and not files.run_button.isEnabled()
        assert ui.window.stop_button.isEnabled()
    finally:
        ui.presenter._set_busy("")


def test_screenshot_after_load_with_live_pose(ui: Ui, files: Path, tmp_path: Path) -> None:
    """Grabs the window offscreen (docs/desktop.png comes from a real X display: test_xcb)."""
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "sample.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.window.program_box.check_button.click()
    ui.idle()
    ui.window.program_box.load_button.click()
    ui.idle()
    ui.window.program_box.run_button.click()
    ui.idle()

    def mid_program() -> bool:
        state = ui.presenter.live.state
        return state is not None and bool(state.running) and state.line == 50

    try:
        wait_until(mid_program, timeout=30)  # the arm is on its way to Pb
    except AssertionError:
        raise AssertionError((ui.dialogs.notices, ui.presenter.live.state, log_text(ui))) from None
    assert ui.take_notices() == []
    ui.window.exec_edit.clear()
    ui.window.program_box.tabs.setCurrentIndex(0)  # the program as loaded
    ui.window.resize(1366, 700)  # a lab laptop's screen: everything readable
    wait_until(lambda: ui.window.pose_values[0].text() != "—")
    for _ in range(5):
        QApplication.processEvents()
    image = ui.window.grab()
    target = tmp_path / "desktop.png"
    assert image.save(str(target))
    assert target.stat().st_size > 10_000


def test_load_and_run_from_a_workspace(ui: Ui, observer: ApiClient, files: Path) -> None:
    """A program written in the IDE (a workspace on the server), chosen under *From:*."""
    ui.take_notices()
    wait_until(lambda: still(observer))
    points = (files / "sample.POS").read_text()
    made = observer._call(
        "POST",
        "/api/workspaces",
        {"name": f"Desk lab {time.monotonic_ns()}", "program": NUMBERED_PROGRAM, "points": points},
    )
    name = made["name"]
    ui.presenter.refresh_workspaces()  # as opening the list does
    box = ui.window.program_box.source_box
    wait_until(lambda: box.findData(made["id"]) > 0)
    box.setCurrentIndex(box.findData(made["id"]))
    ui.idle()
    shown = ui.window.program_box.program_edit
    wait_until(lambda: shown.text() == f"{name} (workspace)  ·  5 lines")
    assert not ui.window.program_box.program_button.isEnabled()  # files are not the source now
    assert ui.window.program_box.points_view.toPlainText() == points
    ui.window.program_box.load_button.click()
    ui.idle()
    assert ui.take_notices() == []
    assert f"Loaded {name} (workspace) into the robot (5 lines" in log_text(ui)
    ui.window.program_box.run_button.click()
    ui.idle()
    now = ui.window.robot_box.status_values["activity"]
    wait_until(lambda: now.text() == f"Running line 4 of {name} (workspace)", timeout=60)
    wait_until(lambda: still(observer), timeout=60)
    box.setCurrentIndex(0)  # back to files: nothing chosen yet
    assert ui.presenter.program is None and ui.window.program_box.program_button.isEnabled()


def test_upload_progress_and_control_are_shown(ui: Ui, observer: ApiClient) -> None:
    def progress(sent: int, user: str) -> LiveMessage:
        message = parse_message({"type": "progress", "actor": {"user": user, "role": "student"},
                              "at": "2026-11-24T09:00:00Z", "command_id": 1,
                              "command": "load_project", "label": "Load project", "sent": sent,
                              "total": 1724})  # fmt: skip
        assert message is not None
        return message

    ui.presenter.live.on_message(progress(300, "someone-else"))
    assert not ui.window.progress.isVisibleTo(ui.window)  # not ours: no bar
    ui.presenter.live.on_message(progress(862, "admin"))
    assert ui.window.progress.isVisibleTo(ui.window) and ui.window.progress.value() == 50
    assert ui.window.statusBar().currentMessage() == "Sending to the robot: 50 %"
    state = ui.presenter.live.state
    assert state is not None
    ui.presenter.live.on_state(state)  # not uploading: the bar goes
    assert not ui.window.progress.isVisibleTo(ui.window)
    ui.window.servo_on_button.click()  # a command: this user holds control
    ui.idle()
    lease = ui.window.robot_box.status_values["lease"]
    wait_until(lambda: lease.text().startswith("you since "))


def test_the_queue_and_its_claim(ui: Ui, observer: ApiClient) -> None:
    """The lab robot's queue in the status bar; when the arm is offered to this user, the
    claim button shows, and its click gives the lease and runs the queued program."""
    program = "SERVO ON\nMOV P1\nEND\n"
    points = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    observer._call("DELETE", "/api/lease")  # earlier tests took it: the arm is free
    joined = observer._call("POST", "/api/queue", {"program": program, "points": points})
    assert joined["entries"][0]["state"] == "offered"  # the same user, another session
    wait_until(lambda: ui.window.claim_button.isVisible())
    assert "offered to you" in ui.window.queue_label.text()
    lease = ui.window.robot_box.status_values["lease"]  # free, but the queue's to give
    wait_until(lambda: lease.text().startswith("by the queue"))
    ui.window.claim_button.click()
    wait_until(lambda: not ui.window.claim_button.isVisible())
    wait_until(lambda: "At the arm: you" in ui.window.queue_label.text())
    assert observer._call("GET", "/api/lease")["you"] is True
    ui.idle()
    observer._call("POST", "/api/queue/done")  # the arm is free again for the other tests
    wait_until(lambda: "empty" in ui.window.queue_label.text())


def test_main_signs_in_opens_the_window_and_exits_when_closed(
    qapp: QApplication, server: Server
) -> None:
    """The real entry point (`melfa desktop`), its modal sign-in driven by timers."""
    from PySide6.QtCore import QTimer

    from melfa.desktop.app import main

    seen: list[str] = []
    others = {id(w) for w in QApplication.topLevelWidgets()}  # e.g. the module's window

    def sign_in_when_asked() -> None:
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, LoginDialog):
            QTimer.singleShot(20, sign_in_when_asked)
            return
        seen.append(dialog.username_edit.text())
        dialog.password_edit.setText(server.password)
        dialog.sign_in_button.click()
        QTimer.singleShot(20, close_when_live)

    def close_when_live() -> None:
        windows = [
            w
            for w in QApplication.topLevelWidgets()
            if isinstance(w, MainWindow) and id(w) not in others
        ]
        live = [w for w in windows if w.isVisible() and w.presenter.live.state is not None]
        if not live:
            QTimer.singleShot(20, close_when_live)
            return
        seen.append(live[0].link_pill.text())
        live[0].close()

    QTimer.singleShot(0, sign_in_when_asked)
    assert main(server.url, "admin") == 0
    assert seen == ["admin", "Robot connected"]


def test_many_updates_keep_none_alive(ui: Ui) -> None:
    """A long session makes thousands of void Qt calls. PySide6-Essentials 6.12.0 dropped a
    reference to None on each under Python 3.11 and aborted the interpreter; pyproject pins
    below it, and this catches a build that does it again."""
    import sys

    state = ui.presenter.live.state
    assert state is not None
    before = sys.getrefcount(None)
    for _ in range(2000):
        ui.window.show_state(state)
    assert sys.getrefcount(None) >= before - 100
