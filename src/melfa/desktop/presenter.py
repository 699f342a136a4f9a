"""Between the widgets and the API: what each button means, done off the GUI thread.

Every API call runs on a worker thread, so a slow controller (an upload at 9600 baud, a
`run` that answers when the controller did) never freezes the window. Commands go one at
a time through one worker; STOP has a worker of its own, so it is never queued behind a
load. Results, live messages and failures come back to the GUI thread (a zero-time
`QTimer.singleShot` on an anchor object living there) and go to the `View`.

The presenter tells its view what to show through plain method calls (a `View`), not Qt
signals, so it can be tested with any view and stays free of Qt's threading rules.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from datetime import datetime
from functools import partial
from pathlib import Path
from typing import Protocol, TypeVar

from PySide6.QtCore import QObject, QTimer

from melfa.desktop.api import (
    TARGET_LABELS,
    ApiClient,
    ApiError,
    CheckResult,
    ServerUnreachable,
    UploadReport,
)
from melfa.desktop.dialogs import Notice, NoticeKind
from melfa.desktop.files import ChosenFile, FileKind, FileRefused, read_file
from melfa.desktop.live import FeedStatus, LiveFeed
from melfa.desktop.messages import (
    CommandFinished,
    Hello,
    LinkChanged,
    LinkStatus,
    LiveMessage,
    RobotState,
    UploadProgress,
)

T = TypeVar("T")


class View(Protocol):
    """What the presenter asks the window to show (always on the GUI thread)."""

    def show_state(self, state: RobotState) -> None: ...
    def show_link(self, status: LinkStatus, detail: str) -> None: ...
    def show_feed(self, status: FeedStatus, detail: str) -> None: ...
    def show_busy(self, what: str) -> None: ...
    def show_files(self) -> None: ...
    def show_check(self, result: CheckResult) -> None: ...
    def show_notice(self, notice: Notice) -> None: ...
    def append_log(self, line: str) -> None: ...
    def show_status(self, text: str) -> None: ...


class NoView:
    """Shows nothing: the presenter before a window is attached."""

    def show_state(self, state: RobotState) -> None:
        pass

    def show_link(self, status: LinkStatus, detail: str) -> None:
        pass

    def show_feed(self, status: FeedStatus, detail: str) -> None:
        pass

    def show_busy(self, what: str) -> None:
        pass

    def show_files(self) -> None:
        pass

    def show_check(self, result: CheckResult) -> None:
        pass

    def show_notice(self, notice: Notice) -> None:
        pass

    def append_log(self, line: str) -> None:
        pass

    def show_status(self, text: str) -> None:
        pass


def diagnostic_lines(result: CheckResult, errors_only: bool = True) -> tuple[str, ...]:
    """``line:col  message`` for the dialog, program first, then points."""
    out: list[str] = []
    for where, diags in (("", result.program), ("points ", result.points)):
        for d in diags:
            if errors_only and d.severity.value != "error":
                continue
            out.append(f"{where}{d.line}:{d.column}  {d.message}")
    return tuple(out)


def describe_failure(exc: BaseException) -> tuple[str, tuple[str, ...]]:
    """A sentence for people (and diagnostic lines) for a failed call, naming whose fault."""
    if isinstance(exc, ApiError):
        lines = tuple(f"{d.line}:{d.column}  {d.message}" for d in exc.diagnostics)
        if exc.status == 503:
            return f"The robot link is down: {exc.message}", lines
        if exc.status >= 500:
            return f"The server failed: {exc.message}", lines
        return exc.message[:1].upper() + exc.message[1:], lines
    if isinstance(exc, ServerUnreachable):
        return f"Cannot reach the server at {exc.url}: {exc.reason}.", ()
    return f"Unexpected failure in the client: {type(exc).__name__}: {exc}", ()


class Presenter:
    """One signed-in client's actions and the live state the window shows.

    Create it on the GUI thread (its anchor object lives there)."""

    def __init__(self, client: ApiClient) -> None:
        self.client = client
        self.view: View = NoView()
        self.program: ChosenFile | None = None
        self.points: ChosenFile | None = None
        self.state: RobotState | None = None
        self.last_upload: UploadReport | None = None
        self.link = LinkStatus.UNKNOWN
        self.feed_status = FeedStatus.CLOSED
        self.busy = ""
        self._anchor = QObject()
        self._commands = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-cmd")
        self._stopper = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-stop")
        self._feed: LiveFeed | None = None
        self._closed = False

    @property
    def closed(self) -> bool:
        return self._closed

    def attach(self, view: View) -> None:
        self.view = view

    # --- plumbing ------------------------------------------------------------------------

    def _later(self, call: Callable[[], None]) -> None:
        """Run ``call`` on the GUI thread (safe from any thread); dropped once closed."""
        if not self._closed:
            QTimer.singleShot(0, self._anchor, partial(self._deliver, call))

    def _deliver(self, call: Callable[[], None]) -> None:
        if not self._closed:
            call()

    def _log(self, text: str) -> None:
        self.view.append_log(f"{datetime.now():%H:%M:%S}  {text}")

    def _tell(self, kind: NoticeKind, title: str, text: str, lines: tuple[str, ...] = ()) -> None:
        self.view.show_notice(Notice(kind, title, text, lines))

    def _set_busy(self, what: str) -> None:
        self.busy = what
        self.view.show_busy(what)

    def _submit(
        self,
        what: str,
        work: Callable[[], T],
        done: Callable[[T], None],
        failed_title: str,
    ) -> bool:
        """Run ``work`` on the command worker; ``done`` or a failure dialog on the GUI thread."""
        if self._closed:
            return False
        if self.busy:
            self.view.show_status(f"Still {self.busy.lower()}; wait for it or press STOP.")
            return False
        self._set_busy(what)

        def job() -> None:
            try:
                result = work()
            except Exception as exc:
                self._later(partial(self._failed, failed_title, exc))
            else:
                self._later(partial(self._finished, done, result))

        self._commands.submit(job)
        return True

    def _finished(self, done: Callable[[T], None], result: T) -> None:
        self._set_busy("")
        done(result)

    def _failed(self, title: str, exc: BaseException) -> None:
        self._set_busy("")
        text, lines = describe_failure(exc)
        self._log(f"{title}: {text}")
        self.view.show_status(f"{title}.")
        self._tell(NoticeKind.ERROR, title, text, lines)

    # --- live feed -----------------------------------------------------------------------

    def choose_target(self, target: str) -> None:
        """Drive ``target`` (``lab`` or ``mine``) from now on: the live feed follows it."""
        if target == self.client.target:
            return
        self.client.target = target
        self._log(f"Now driving {TARGET_LABELS.get(target, target)}")
        if self._feed is not None:
            self._feed.close(timeout=1.0)
            self._feed = None
            self.start()

    def start(self) -> None:
        """Show the latest state now, then follow the WebSocket."""
        self._submit("Reading the state", self.client.state, self._on_state, "Could not read")
        self._feed = LiveFeed(
            self.client.websocket_url,
            self.client.cookie_header(),
            lambda message: self._later(partial(self._on_live, message)),
            lambda status, detail: self._later(partial(self._on_feed, status, detail)),
        )
        self._feed.start()

    def _on_live(self, message: LiveMessage) -> None:
        if isinstance(message, RobotState):
            self._on_state(message)
        elif isinstance(message, LinkChanged):
            self._set_link(message.status, message.detail)
            self._log(
                f"Robot link {message.status.value}" + f": {message.detail}" * bool(message.detail)
            )
        elif isinstance(message, Hello):
            self._set_link(message.link, "")
            self._log(f"Live feed open as {message.user} ({message.role}); robot {message.robot}")
        elif isinstance(message, CommandFinished):
            if message.ok:
                # "run" answers when the program has started, not when it has finished.
                what = "started" if message.command == "run" else "done"
                self._log(f"{message.command} {what} (by {message.actor or 'the service'})")
            else:
                number = f" [{message.error_number}]" if message.error_number else ""
                self._log(f"{message.command} failed{number}: {message.error}")
        elif isinstance(message, UploadProgress) and message.total:
            self.view.show_status(f"Uploading: {message.sent} of {message.total} lines")

    def _on_state(self, state: RobotState) -> None:
        self.state = state
        if state.link is not LinkStatus.UNKNOWN and state.link is not self.link:
            self._set_link(state.link, "")
        self.view.show_state(state)

    def _set_link(self, status: LinkStatus, detail: str) -> None:
        self.link = status
        self.view.show_link(status, detail)

    def _on_feed(self, status: FeedStatus, detail: str) -> None:
        self.feed_status = status
        self.view.show_feed(status, detail)
        if status is FeedStatus.REFUSED:
            self._log(f"Live feed refused: {detail}")
            self._tell(
                NoticeKind.ERROR,
                "Live updates stopped",
                f"The server refused the live feed ({detail}). Sign in again.",
            )
        elif status is FeedStatus.DISCONNECTED:
            self.view.show_status(f"Live feed lost ({detail}); reconnecting…")

    # --- files ---------------------------------------------------------------------------

    def choose(self, kind: FileKind, path: Path) -> bool:
        """Take a chosen file; a wrong extension (or unreadable file) is refused at once."""
        try:
            chosen = read_file(path, kind)
        except FileRefused as exc:
            self._refuse_file(exc)
            return False
        if kind is FileKind.PROGRAM:
            self.program = chosen
        else:
            self.points = chosen
        self.view.show_files()
        self.view.show_status(f"Chose {kind.label} {path.name}.")
        return True

    def _refuse_file(self, exc: FileRefused) -> None:
        title = (
            "Wrong extension" if "extension" in exc.reason else f"Cannot use this {exc.kind.label}"
        )
        self._log(f"Refused {exc.path.name}: {exc.reason}")
        self._tell(NoticeKind.ERROR, title, f"{exc.path.name}: {exc.reason}.")

    def _reread(self) -> tuple[ChosenFile, ChosenFile | None] | None:
        """The chosen files as they are on disk now (edited since? load the edit)."""
        if self.program is None:
            self._tell(
                NoticeKind.WARNING, "No program", "Choose a program file (.MB4) to load first."
            )
            return None
        try:
            program = read_file(self.program.path, FileKind.PROGRAM)
            points = None if self.points is None else read_file(self.points.path, FileKind.POINTS)
        except FileRefused as exc:
            self._refuse_file(exc)
            return None
        self.program, self.points = program, points
        return program, points

    # --- commands ------------------------------------------------------------------------

    def check(self) -> bool:
        """Check the chosen files (`/api/check`) and show the diagnostics; sends nothing."""
        files = self._reread()
        if files is None:
            return False
        program, points = files
        points_text = points.text if points else ""
        return self._submit(
            "Checking",
            lambda: self.client.check(program.text, points_text),
            self._on_checked,
            "Check failed",
        )

    def _on_checked(self, result: CheckResult) -> None:
        self.view.show_check(result)
        errors = len(result.program_errors) + len(result.points_errors)
        others = len(result.program) + len(result.points) - errors
        self.view.show_status(f"Check: {errors} error(s), {others} other finding(s).")

    def load(self) -> bool:
        """Check, then load program and points into slot 1; errors refuse with a dialog."""
        files = self._reread()
        if files is None:
            return False
        program, points = files
        points_text = points.text if points else ""

        def work() -> CheckResult | UploadReport:
            result = self.client.check(program.text, points_text)
            self._later(partial(self._show_check, result))
            if not result.ok:
                return result
            return self.client.load_project(program.text, points_text)

        self._log(f"Loading {program.path.name}" + (f" with {points.path.name}" if points else ""))
        return self._submit(
            "Loading", work, partial(self._on_loaded, program, points), "Load refused"
        )

    def _on_loaded(
        self, program: ChosenFile, points: ChosenFile | None, outcome: CheckResult | UploadReport
    ) -> None:
        if isinstance(outcome, CheckResult):
            bad = (
                program.path.name
                if outcome.program_errors
                else (points.path.name if points else "")
            )
            count = len(outcome.program_errors) + len(outcome.points_errors)
            text = f"{bad} has {count} error{'s' * (count != 1)}; nothing was sent to the robot."
            self._log(f"Load refused: {text}")
            self.view.show_status("Load refused: the program has errors.")
            self._tell(NoticeKind.ERROR, "Program has errors", text, diagnostic_lines(outcome))
            return
        self._log(
            f"Loaded {program.path.name}: {outcome.items} items, {outcome.bytes_sent} bytes"
            f" in {outcome.seconds:.2f} s"
        )
        self.view.show_status(f"Loaded {program.path.name} into slot 1.")
        self.last_upload = outcome

    def run(self) -> bool:
        """Start the program loaded in slot 1."""
        self._log("Run")
        return self._submit("Starting", self.client.run, self._on_ran, "Run refused")

    def _show_check(self, result: CheckResult) -> None:
        self.view.show_check(result)

    def _status(self, text: str) -> None:
        self.view.show_status(text)

    def _on_ran(self, _: None) -> None:
        self.view.show_status("Program started.")

    def reset_alarm(self) -> bool:
        """Clear the controller's error (RSTALRM), e.g. after a refused instruction."""
        self._log("Reset alarm")
        return self._submit(
            "Resetting the alarm",
            self.client.reset_alarm,
            lambda _: self._status("Alarm reset."),
            "Reset refused",
        )

    def servo(self, on: bool) -> bool:
        """Switch the servo on or off."""
        self._log(f"Servo {'on' if on else 'off'}")
        return self._submit(
            "Switching the servo",
            lambda: self.client.servo(on),
            lambda _: self._status(f"Servo {'on' if on else 'off'}."),
            "Servo refused",
        )

    def set_override(self, percent: int) -> bool:
        """Set the speed override (1–100 %)."""
        self._log(f"Override {percent} %")
        return self._submit(
            "Setting the override",
            lambda: self.client.override(percent),
            lambda value: self._status(f"Override {value} %."),
            "Override refused",
        )

    def jog(self, frame: str, axis: int, direction: int) -> bool:
        """One jog step (the button names the axis and the sign)."""
        names = ("J1", "J2", "J3", "J4", "J5", "J6") if frame == "joint" else "XYZABC"
        label = f"{names[axis]}{'+' if direction > 0 else '-'}"
        self._log(f"Jog {frame} {label}")
        return self._submit(
            "Jogging",
            lambda: self.client.jog_step(frame, axis, direction),
            lambda _: self._status(f"Jogged {label} ({frame})."),
            "Jog refused",
        )

    def exec_statement(self, text: str) -> bool:
        """Send one MELFA BASIC statement (EXEC)."""
        statement = text.strip()
        if not statement:
            self.view.show_status("Type an instruction first, e.g. MOV P1 or HOPEN 1.")
            return False
        self._log(f"Exec {statement}")
        return self._submit(
            "Executing",
            lambda: self.client.exec_statement(statement),
            lambda _: self._status(f"Done: {statement}"),
            "Instruction refused",
        )

    def stop(self) -> None:
        """STOP: on its own worker, never queued behind a command; always allowed."""
        if self._closed:
            return
        self._log("STOP")
        self.view.show_status("STOP sent…")

        def job() -> None:
            try:
                self.client.stop()
            except Exception as exc:
                self._later(partial(self._failed_stop, exc))
            else:
                self._later(partial(self._status, "Stopped."))

        self._stopper.submit(job)

    def _failed_stop(self, exc: BaseException) -> None:
        text, _ = describe_failure(exc)
        self._log(f"STOP failed: {text}")
        self._tell(
            NoticeKind.ERROR,
            "STOP failed",
            f"{text} Use the emergency stop on the teaching pendant or controller.",
        )

    def shutdown(self) -> None:
        """Close the feed, drop queued work, sign out (best effort). Idempotent."""
        if self._closed:
            return
        self._closed = True
        if self._feed is not None:
            self._feed.close()
        self._commands.shutdown(wait=False, cancel_futures=True)
        self._stopper.shutdown(wait=False, cancel_futures=True)
        with contextlib.suppress(ApiError, ServerUnreachable):
            self.client.logout()


__all__ = ["NoView", "Presenter", "View", "describe_failure", "diagnostic_lines"]
