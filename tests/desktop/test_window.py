"""The window offscreen against a served virtual robot: sign-in, refusals with dialogs,
load and run reaching the controller, live pose, STOP, and a screenshot."""

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

from PySide6.QtWidgets import QApplication, QWidget

from melfa.desktop.api import ApiClient
from melfa.desktop.app import application
from melfa.desktop.dialogs import Notice, NoticeKind
from melfa.desktop.files import FileKind
from melfa.desktop.live import FeedStatus
from melfa.desktop.login import LoginDialog
from melfa.desktop.messages import LinkStatus
from melfa.desktop.presenter import Presenter
from melfa.desktop.window import MainWindow
from tests.desktop.conftest import EXAMPLES, Server

LOOP_PROGRAM = """10 SERVO ON
20 OVRD 20
30 *LOOP
40 MOV Pa
50 MOV Pb
60 GOTO *LOOP
"""
FAULTY_PROGRAM = "10 SERVO ON\n20 MOV Pa\n30 FOO 1\n40 MOVE Pb\n"


class RecordingDialogs:
    """The window's dialog hook for tests: records what the user would be told and
    answers file choosers from a queue, with no modal loop."""

    def __init__(self) -> None:
        self.notices: list[Notice] = []
        self.files: list[Path] = []

    def show(self, notice: Notice, parent: QWidget | None) -> None:
        self.notices.append(notice)

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
    (folder / "faulty.MB4").write_text(FAULTY_PROGRAM)
    (folder / "notes.txt").write_text("10 END\n")
    return folder


@dataclass
class Ui:
    window: MainWindow
    presenter: Presenter
    dialogs: RecordingDialogs

    def take_notices(self) -> list[Notice]:
        out, self.dialogs.notices = self.dialogs.notices, []
        return out

    def choose(self, kind: FileKind, path: Path) -> None:
        """Click "Choose…" and pick ``path`` in the (recorded) file dialog."""
        self.dialogs.files.append(path)
        button = (
            self.window.program_button if kind is FileKind.PROGRAM else self.window.points_button
        )
        button.click()

    def idle(self) -> None:
        wait_until(lambda: not self.presenter.busy, timeout=60)


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
        lambda: presenter.state is not None and presenter.feed_status is FeedStatus.CONNECTED
    )
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
    assert ui.window.link_pill.text() == "Connected"
    assert ui.presenter.link is LinkStatus.CONNECTED
    state = ui.presenter.state
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
    assert "notes.txt" not in ui.window.program_edit.text()
    assert "sample.MB4" not in ui.window.points_edit.text()


def test_faulty_program_is_refused_with_its_diagnostics(
    ui: Ui, files: Path, observer: ApiClient
) -> None:
    before = observer.state().seq
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "faulty.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    assert ui.window.load_button.isEnabled()
    ui.window.load_button.click()
    ui.idle()
    [notice] = ui.take_notices()
    assert (notice.kind, notice.title) == (NoticeKind.ERROR, "Program has errors")
    assert notice.text == "faulty.MB4 has 2 errors; nothing was sent to the robot."
    assert notice.lines[0].startswith("3:4  ") and "FOO" in notice.lines[0]
    assert notice.lines[1].startswith("4:4  ")
    assert "3:4  " in notice.listing
    # the check panel lists the same findings
    rows = [
        ui.window.diagnostics.topLevelItem(i)
        for i in range(ui.window.diagnostics.topLevelItemCount())
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
    ui.choose(FileKind.PROGRAM, files / "sample.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.presenter.last_upload = None
    ui.window.load_button.click()
    ui.idle()
    assert ui.take_notices() == []
    assert ui.presenter.last_upload is not None and ui.presenter.last_upload.items >= 7
    assert "Loaded sample.MB4" in ui.window.log.toPlainText()

    start_joints = observer.state().joints
    ui.window.run_button.click()
    ui.idle()
    assert ui.take_notices() == []

    # The server (asked by another session) sees the program run and the arm move...
    wait_until(lambda: observer.state().running is True, timeout=30)
    wait_until(lambda: observer.state().joints != start_joints, timeout=30)
    # ...to its END (step 70), and the window shows it live, from the WebSocket, as the
    # line of the student's file (the server's step -> line map), with the step beside it.
    upload = ui.presenter.last_upload
    assert upload is not None
    end_line = upload.step_lines[70]
    assert end_line == 7  # sample.MB4's last line
    wait_until(
        lambda: ui.window.status_values["line"].text() == f"{end_line} (step 70)", timeout=60
    )
    wait_until(lambda: ui.presenter.state is not None and ui.presenter.state.running is False)
    wait_until(lambda: ui.presenter.state is not None and ui.presenter.state.moving is False)
    final = ui.presenter.state
    assert final is not None and final.joints is not None and final.pose is not None
    wait_until(lambda: ui.window.joint_values[0].text() == f"{final.joints[0]:.2f}")
    assert ui.window.status_values["state"].text() == "Stopped"
    assert ui.window.status_values["servo"].text() == "On"


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
        now = ui.presenter.state
        return now is not None and now.pose is not None and now.pose[2] < z_before - 25

    wait_until(lowered, timeout=30)
    wait_until(lambda: ui.presenter.state is not None and not ui.presenter.state.moving)
    now = ui.presenter.state
    assert now is not None and now.pose is not None
    wait_until(lambda: ui.window.pose_values[2].text() == f"{now.pose[2]:.2f}")
    observed = observer.state().pose
    assert observed is not None and abs(observed[2] - (z_before - 30)) < 0.5


def test_servo_override_and_jog_controls(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    wait_until(lambda: observer.state().moving is False and observer.state().running is False)
    ui.window.servo_off_button.click()
    ui.idle()
    wait_until(lambda: observer.state().servo is False)
    ui.window.override_spin.setValue(25)
    ui.window.override_button.click()
    ui.idle()
    wait_until(lambda: observer.state().override == 25)
    before = observer.state().pose
    assert before is not None
    assert ui.window.jog_buttons[(0, 1)].text() == "X+"
    ui.window.jog_buttons[(0, 1)].click()  # asking to move: the servo comes on, audited
    ui.idle()
    assert ui.take_notices() == []
    wait_until(lambda: observer.state().servo is True)

    def moved() -> bool:
        pose = observer.state().pose
        return pose is not None and pose[0] > before[0] + 0.5

    wait_until(moved, timeout=30)
    ui.window.jog_frame.setCurrentIndex(2)
    assert ui.window.jog_buttons[(2, -1)].text() == "J3−"


def test_a_refused_instruction_says_why(ui: Ui, observer: ApiClient) -> None:
    ui.take_notices()
    # A jog step of the test before may still be moving: then the refusal would be "busy".
    wait_until(lambda: observer.state().moving is False and observer.state().running is False)
    ui.window.exec_edit.setText("MOV P_NOWHERE_AT_ALL")
    ui.window.exec_button.click()
    ui.idle()
    [notice] = ui.take_notices()
    assert notice.title == "Instruction refused"
    assert "MOV P_NOWHERE_AT_ALL" in notice.text  # the controller's refusal, named
    wait_until(lambda: ui.window.status_values["alarm"].text() != "None")
    ui.window.reset_alarm_button.click()
    ui.idle()
    assert ui.take_notices() == []
    wait_until(lambda: ui.window.status_values["alarm"].text() == "None")


def test_stop_stops_a_running_program(ui: Ui, files: Path, observer: ApiClient) -> None:
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "loop.mb4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.window.load_button.click()
    ui.idle()
    assert ui.take_notices() == []
    ui.window.run_button.click()
    ui.idle()
    wait_until(lambda: observer.state().running is True, timeout=30)
    assert ui.window.stop_button.isEnabled()
    ui.window.stop_button.click()
    wait_until(lambda: observer.state().running is False, timeout=30)
    wait_until(lambda: ui.window.status_values["state"].text() == "Stopped")
    assert ui.take_notices() == []
    assert "STOP" in ui.window.log.toPlainText()


def test_stop_stays_enabled_while_busy(ui: Ui) -> None:
    ui.presenter._set_busy("Loading")
    try:
        assert not ui.window.load_button.isEnabled() and not ui.window.run_button.isEnabled()
        assert ui.window.stop_button.isEnabled()
    finally:
        ui.presenter._set_busy("")


def test_screenshot_after_load_with_live_pose(ui: Ui, files: Path, tmp_path: Path) -> None:
    """Grabs the window; with $MELFA_DESKTOP_SCREENSHOT set it saves there (docs/desktop.png)."""
    ui.take_notices()
    ui.choose(FileKind.PROGRAM, files / "sample.MB4")
    ui.choose(FileKind.POINTS, files / "sample.POS")
    ui.window.check_button.click()
    ui.idle()
    ui.window.load_button.click()
    ui.idle()
    ui.window.run_button.click()
    ui.idle()

    def mid_program() -> bool:
        state = ui.presenter.state
        return state is not None and bool(state.running) and state.line == 50

    wait_until(mid_program, timeout=30)  # the arm is on its way to Pb
    assert ui.take_notices() == []
    ui.window.exec_edit.clear()
    ui.window.tabs.setCurrentIndex(0)  # the program as loaded
    ui.window.resize(1366, 700)  # a lab laptop's screen: everything readable
    wait_until(lambda: ui.window.pose_values[0].text() != "—")
    for _ in range(5):
        QApplication.processEvents()
    image = ui.window.grab()
    target = Path(os.environ.get("MELFA_DESKTOP_SCREENSHOT") or tmp_path / "desktop.png")
    assert image.save(str(target))
    assert target.stat().st_size > 10_000


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
        live = [w for w in windows if w.isVisible() and w.presenter.state is not None]
        if not live:
            QTimer.singleShot(20, close_when_live)
            return
        seen.append(live[0].link_pill.text())
        live[0].close()

    QTimer.singleShot(0, sign_in_when_asked)
    assert main(server.url, "admin") == 0
    assert seen == ["admin", "Connected"]


def test_many_updates_keep_none_alive(ui: Ui) -> None:
    """A long session makes thousands of void Qt calls. PySide6-Essentials 6.12.0 dropped a
    reference to None on each under Python 3.11 and aborted the interpreter; pyproject pins
    below it, and this catches a build that does it again."""
    import sys

    state = ui.presenter.state
    assert state is not None
    before = sys.getrefcount(None)
    for _ in range(2000):
        ui.window.show_state(state)
    assert sys.getrefcount(None) >= before - 100
