"""The real client on a real X display: `melfa desktop` (Qt's xcb platform) on Debian's Xvfb
at 1366×700, driven by real key events from xdotool, against the served virtual robot.

A user's whole first run, by keyboard: the password typed into the sign-in dialog, the
program and points chosen in Qt's real file dialogs, Load, Run (the running line of the
file on screen), a refused instruction whose notice stays open while STOP is clicked behind
it and two more notices in a row, then a jog with W held down past X's auto-repeat delay
(xdotool keydown … keyup, auto-repeat on): one jog on the server, moving while the key is
held and stopping when it is let go, the status bar saying so (read as a screen reader reads
it, over AT-SPI: `tests.desktop.a11y`); Esc stops a jog whose key is still down. A second
session of the same user watches the robot through the API, so each step is proven on the
robot, not on the screen. The screenshot in docs/desktop.png is this window
(MELFA_DESKTOP_SCREENSHOT=docs/desktop.png saves it there).

Xvfb, xdotool, dbus-daemon, dbus-bin and at-spi2-core are Debian packages `scripts/setup`
installs when run as root (CI does); without them these tests skip and say so.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from melfa.desktop.api import ApiClient
from melfa.vocab.activity import Activity
from melfa.vocab.jog import JogEnd
from tests.desktop.a11y import MISSING, Accessibility, accessibility
from tests.desktop.conftest import EXAMPLES, Server
from tests.waiting import wait_until

XVFB = shutil.which("Xvfb")
XDOTOOL = shutil.which("xdotool")
XSET = shutil.which("xset")
"""Sets X's key auto-repeat (Debian's x11-xserver-utils); without it, Xvfb's default (on)."""
pytestmark = [
    pytest.mark.skipif(
        XVFB is None or XDOTOOL is None,
        reason="needs Debian's xvfb and xdotool (scripts/setup installs them as root)",
    ),
    pytest.mark.skipif(
        bool(MISSING),
        reason=f"needs Debian's {', '.join(MISSING)} (scripts/setup installs them as root)",
    ),
]
pytest.importorskip("PySide6.QtWidgets", reason="the desktop extra (PySide6) is not installed")

WIDTH, HEIGHT = 1366, 700
LOOP = "100 SERVO ON\n110 OVRD 30\n120 *LOOP\n130 MOV Pa\n140 MOV Pb\n150 GOTO *LOOP\n"
"""Numbered from 100, so the running steps (130, 140) prove this program was loaded."""


def wait_for(condition: Callable[[], object], what: str, timeout: float = 30.0) -> None:
    """`tests.waiting.wait_until` with the thing awaited first (it reads better here)."""
    wait_until(condition, timeout, what)


@pytest.fixture(scope="module")
def display() -> Iterator[dict[str, str]]:
    """A fresh Xvfb screen of 1366×700 at 96 dpi; the environment that uses it."""
    read_fd, write_fd = os.pipe()
    assert XVFB is not None
    proc = subprocess.Popen(
        [XVFB, "-displayfd", str(write_fd), "-screen", "0", f"{WIDTH}x{HEIGHT}x24", "-dpi", "96"],
        pass_fds=(write_fd,),
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    os.close(write_fd)
    with os.fdopen(read_fd) as pipe:
        number = pipe.readline().strip()  # Xvfb writes the display it took once it listens
    if not number:
        proc.kill()
        pytest.fail("Xvfb did not start")
    env = {k: v for k, v in os.environ.items() if k not in ("QT_QPA_PLATFORM", "WAYLAND_DISPLAY")}
    env.update(DISPLAY=f":{number}", QT_QPA_PLATFORM="xcb")
    try:
        yield env
    finally:
        proc.terminate()
        proc.wait(timeout=10)


class Desktop:
    """The `melfa desktop` process, the keyboard xdotool types on and what its window
    shows a screen reader."""

    def __init__(self, a11y: Accessibility, proc: subprocess.Popen[bytes], log: Path) -> None:
        self.env = a11y.env
        self.a11y = a11y
        self.proc = proc
        self.log = log

    def status_bar(self) -> str:
        """The window's status bar message, as AT-SPI gives it to a screen reader."""
        return self.a11y.status_bar()

    def xdo(self, *args: str) -> str:
        assert XDOTOOL is not None
        done = subprocess.run(
            [XDOTOOL, *args], env=self.env, capture_output=True, text=True, timeout=30
        )
        return done.stdout.strip()

    def windows(self, name: str) -> list[str]:
        return self.xdo("search", "--onlyvisible", "--name", name).split()

    def focus(self, name: str, timeout: float = 30.0) -> str:
        """The window whose title matches ``name``, once shown; it gets the keyboard."""

        def shown() -> bool:
            assert self.proc.poll() is None, self.log.read_text()
            return bool(self.windows(name))

        wait_for(shown, f"a window named {name!r}", timeout)
        window = self.windows(name)[-1]
        self.xdo("windowfocus", "--sync", window)
        return window

    def run(self, *command: str) -> None:
        subprocess.run(command, env=self.env, check=True, timeout=30)

    def key(self, *keys: str) -> None:
        self.xdo("key", "--clearmodifiers", *keys)

    def type(self, text: str) -> None:
        self.xdo("type", "--delay", "15", text)

    def choose_file(self, shortcut: str, title: str, name: str) -> None:
        """Alt+P / Alt+O, then the file's name typed into Qt's file dialog and Enter."""
        for _ in range(3):  # the window may not have the keyboard yet when it first shows
            self.focus("melfa desktop")
            self.key(shortcut)
            try:
                self.focus(title, timeout=10)
                break
            except AssertionError:
                continue
        self.type(name)
        for _ in range(3):  # a first Enter may only accept the completer's suggestion
            if not self.windows(title):
                return
            self.key("Return")
            try:
                wait_for(lambda: not self.windows(title), f"{title} to close", 10)
                return
            except AssertionError:
                continue
        raise AssertionError(f"the file dialog {title!r} did not take {name}")


@pytest.fixture(scope="module")
def desktop(
    display: dict[str, str], server: Server, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[Desktop]:
    """`melfa desktop --server … --user admin`, started in a folder with the files."""
    folder = tmp_path_factory.mktemp("xcb-files")
    shutil.copy(EXAMPLES / "sample.POS", folder / "sample.POS")
    (folder / "loop.MB4").write_text(LOOP)
    log = folder / "desktop.log"
    with accessibility(display) as a11y:
        with log.open("wb") as out:
            proc = subprocess.Popen(
                [
                    *(sys.executable, "-m", "melfa", "desktop"),
                    *("--server", server.url, "--user", "admin"),
                ],
                cwd=folder,  # the file dialog opens here
                env=a11y.env,
                stdout=out,
                stderr=subprocess.STDOUT,
            )
        desk = Desktop(a11y, proc, log)
        try:
            yield desk
        finally:
            if proc.poll() is None:
                proc.terminate()
                proc.wait(timeout=10)


@pytest.fixture(scope="module")
def observer(server: Server) -> ApiClient:
    """The same user's second session: proof that each step reached the robot."""
    client = ApiClient(server.url)
    client.login("admin", server.password)
    return client


def audited(observer: ApiClient, action: str) -> list[dict[str, object]]:
    reply = observer._call("GET", f"/api/audit?action={action}&limit=20")
    return list(reply["entries"])


def still(observer: ApiClient) -> bool:
    state = observer.state()
    idle = state.activity in (Activity.IDLE, Activity.PAUSED, Activity.AT)  # not moving
    return not state.moving and not state.running and not state.jogging and idle


def grab_screen(env: dict[str, str], target: Path) -> None:
    """The X screen as the user sees it, read back from the X server by Qt (xcb)."""
    code = (
        "import sys\nfrom PySide6.QtGui import QGuiApplication\n"
        "app = QGuiApplication(sys.argv[:1])\n"
        "assert app.primaryScreen().grabWindow(0).save(sys.argv[1])\n"
    )
    subprocess.run([sys.executable, "-c", code, str(target)], env=env, check=True, timeout=60)


def sign_in_by_typing_the_password(desktop: Desktop, server: Server) -> None:
    desktop.focus("Sign in")
    desktop.type(server.password)  # the dialog starts in the password box (--user given)
    desktop.key("Return")
    window = desktop.focus("melfa desktop")
    geometry = desktop.xdo("getwindowgeometry", window)
    assert f"Geometry: {WIDTH}x{HEIGHT}" in geometry  # fills a 1366×700 screen, no larger
    assert not desktop.windows("Sign in")


def choose_load_and_run_by_keyboard(desktop: Desktop, observer: ApiClient, shot: Path) -> None:
    loads_before = len(audited(observer, "robot.load_project"))
    desktop.choose_file("alt+p", "Choose a program", "loop.MB4")
    desktop.choose_file("alt+o", "Choose a points file", "sample.POS")
    desktop.focus("melfa desktop")
    desktop.key("alt+l")  # Load into robot

    def loaded() -> bool:
        entries = audited(observer, "robot.load_project")
        return len(entries) > loads_before and entries[0]["result"] == "ok"

    wait_for(loaded, "the load to be audited as done", 120)
    desktop.key("alt+r")  # Run program
    wait_for(lambda: observer.state().running is True, "the program to run")
    wait_for(lambda: observer.state().line in (130, 140), "the loop's moves")
    # The screenshot (docs/desktop.png): mid-run, the running line of loop.MB4 on screen.
    wait_for(lambda: observer.state().line == 140, "the move to Pb")
    grab_screen(desktop.env, shot)
    assert shot.stat().st_size > 20_000


def stop_works_behind_a_notice(desktop: Desktop, observer: ApiClient) -> None:
    """A refusal's notice does not block the window: STOP is clicked with the mouse while
    it is open (the program runs on), and the program stops."""
    assert observer.state().running is True
    desktop.focus("melfa desktop")
    desktop.key("alt+i")
    desktop.type("MOV P1")
    desktop.key("Return")  # refused while the program runs: a notice opens
    desktop.focus("Instruction refused")
    assert observer.state().running is True
    # STOP is the header's right-most button (the window fills the screen from 0, 0).
    desktop.xdo("mousemove", "--sync", str(WIDTH - 90), "36", "click", "1")
    wait_for(lambda: observer.state().running is False, "STOP to stop the program")
    wait_for(lambda: still(observer), "the arm to stand still")
    desktop.focus("Instruction refused")
    desktop.key("Return")  # OK closes the notice
    wait_for(lambda: not desktop.windows("Instruction refused"), "the notice to close")


def notices_keep_coming_after_one_is_closed(desktop: Desktop, observer: ApiClient) -> None:
    """Two more refusals in a row, each notice shown and closed with OK (the second notice
    after a closed one once failed: "Internal C++ object already deleted")."""
    for _ in range(2):
        desktop.focus("melfa desktop")
        desktop.key("alt+i")
        desktop.key("ctrl+a")
        desktop.type("MOVV P1")  # not a statement: refused, with its reason, in a notice
        desktop.key("Return")
        desktop.focus("Instruction refused")
        desktop.key("Return")
        wait_for(lambda: not desktop.windows("Instruction refused"), "the notice to close")
    if observer.state().alarm is not None:
        observer.reset_alarm()
    assert "Traceback" not in desktop.log.read_text(errors="replace")


def pose(observer: ApiClient) -> tuple[float, ...]:
    value = observer.state().pose
    assert value is not None
    return value


def stays_put(observer: ApiClient) -> None:
    """Still, and the pose unchanged over several fresh snapshots (0.2 mm: the computed and
    the controller's rounded pose differ by ~0.06 mm; a jog moves far more). Snapshots
    taken after the release first: one from before it may not show the arm moving yet."""
    seq = observer.state().seq
    wait_for(lambda: observer.state().seq >= seq + 5 and still(observer), "a still arm")
    before, seq = pose(observer), observer.state().seq
    wait_for(lambda: observer.state().seq >= seq + 5, "fresh snapshots")
    after = pose(observer)
    assert max(abs(a - b) for a, b in zip(before, after, strict=True)) < 0.2, (before, after)


def jog_starts(observer: ApiClient) -> set[object]:
    """The jogs the server audited (each as accepted and as ended: one command id)."""
    reply = observer._call("GET", "/api/audit?action=robot.jog&limit=500")
    return {entry["details"]["command_id"] for entry in reply["entries"]}


def a_held_w_key_jogs_only_while_held(desktop: Desktop, observer: ApiClient) -> None:
    """W held well past X's auto-repeat delay, with auto-repeat on (X's default; the rate
    set so the repeats surely come): one jog on the server, from key-down to key-up."""
    if XSET is not None:
        desktop.run(XSET, "r", "on")
        desktop.run(XSET, "r", "rate", "250", "30")  # repeats after 0.25 s, 30 a second
    desktop.focus("melfa desktop")
    desktop.key("alt+j")  # the jog pad takes the keyboard
    start = pose(observer)
    before = jog_starts(observer)
    wait_for(desktop.a11y.has_status_bar, "the status bar, found as a screen reader finds it")
    desktop.xdo("keydown", "w")
    try:
        wait_for(lambda: observer.state().jogging, "the jog to start while W is held")
        wait_for(lambda: pose(observer)[0] > start[0] + 5, "X to grow while W is held")
        # While held, the status bar says how to stop (a screen reader reads it too).
        wait_for(
            lambda: re.fullmatch(r"Jogging X\+.*let go to stop\.", desktop.status_bar()),
            "the status bar to say the jog runs until W is let go",
        )
        desktop.xdo("sleep", "1.5")  # the key stays down past the repeat delay (the stimulus)
        assert observer.state().jogging  # still held: still jogging (auto-repeat ignored)
    finally:
        desktop.xdo("keyup", "w")
    wait_for(lambda: not observer.state().jogging, "the jog to end when W is let go")
    # Once let go, what is true then (it went on saying "let go to stop").
    released = f"Jog stopped: {JogEnd.RELEASED.words()}."
    wait_for(lambda: desktop.status_bar() == released, f"the status bar to say {released!r}")
    stays_put(observer)
    assert desktop.status_bar() == released
    assert pose(observer)[0] > start[0] + 5
    assert len(jog_starts(observer) - before) == 1  # one hold, one jog: never restarted


def escape_stops_a_jog_whose_key_is_still_down(desktop: Desktop, observer: ApiClient) -> None:
    desktop.focus("melfa desktop")
    desktop.key("alt+j")
    desktop.xdo("keydown", "s")
    try:
        wait_for(lambda: observer.state().jogging, "the jog to start while S is held")
        desktop.key("Escape")  # STOP, with S still down
        wait_for(lambda: not observer.state().jogging, "STOP to end the jog")
        stays_put(observer)
    finally:
        desktop.xdo("keyup", "s")


def test_a_first_run_by_keyboard_on_a_real_display(
    desktop: Desktop, server: Server, observer: ApiClient, tmp_path: Path
) -> None:
    """One user's session in order (each step needs the one before it)."""
    if observer.state().alarm is not None:  # left by another test: arrange a clean start
        observer.reset_alarm()
    wait_for(lambda: still(observer), "the robot to be still")
    shot = Path(os.environ.get("MELFA_DESKTOP_SCREENSHOT") or tmp_path / "desktop.png")
    try:
        sign_in_by_typing_the_password(desktop, server)
        choose_load_and_run_by_keyboard(desktop, observer, shot)
        stop_works_behind_a_notice(desktop, observer)
        notices_keep_coming_after_one_is_closed(desktop, observer)
        a_held_w_key_jogs_only_while_held(desktop, observer)
        escape_stops_a_jog_whose_key_is_still_down(desktop, observer)
    except AssertionError as exc:  # what the screen showed, for whoever reads the failure
        seen = tmp_path / "failed.png"
        if desktop.proc.poll() is None:
            grab_screen(desktop.env, seen)
        log = desktop.log.read_text(errors="replace")[-2000:]
        raise AssertionError(f"{exc} (screen: {seen}; client output: {log!r})") from exc
    # Ctrl+Q signs out and quits cleanly.
    desktop.focus("melfa desktop")
    desktop.key("ctrl+q")
    assert desktop.proc.wait(timeout=30) == 0
    log = desktop.log.read_text(errors="replace")
    assert "Traceback" not in log, log
