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
import logging
from collections.abc import Callable, Mapping
from concurrent.futures import ThreadPoolExecutor
from datetime import datetime
from functools import partial
from pathlib import Path
from typing import TypeVar

from PySide6.QtCore import QObject, QTimer

from melfa.desktop.api import (
    TARGET_LABELS,
    ApiClient,
    ApiError,
    CheckResult,
    ServerUnreachable,
    UploadReport,
    WorkspaceInfo,
)
from melfa.desktop.dialogs import Notice, NoticeKind
from melfa.desktop.files import ChosenFile, FileKind, FileRefused, from_workspace, read_file
from melfa.desktop.hold import JogHold, JogKey
from melfa.desktop.live import FeedStatus, LiveFeed
from melfa.desktop.messages import LiveMessage, actor_name, error_fix
from melfa.desktop.view import NoView, View
from melfa.desktop.words import (
    Loaded,
    count,
    describe_failure,
    diagnostic_lines,
    jog_label,
    link_words,
    queue_line,
    sentence,
    upload_progress,
)
from melfa.live.messages import (
    CommandResultMessage,
    ErrorMessage,
    Hello,
    JogHeartbeatAck,
    JogMessage,
    LinkMessage,
    ProgressMessage,
    QueueMessage,
    StateOut,
)
from melfa.protocol.advice import Fix
from melfa.vocab.commands import Command, command_label
from melfa.vocab.jog import JogEnd
from melfa.vocab.link import LinkStatus

_log = logging.getLogger(__name__)
FIXES_OFFERED = frozenset({Fix.SERVO_ON_RETRY, Fix.RESET_ALARM, Fix.LOAD_PROJECT, Fix.STOP})
"""The one-click fixes this client can do (adding a point needs the IDE's points editor)."""

T = TypeVar("T")


class Presenter:
    """One signed-in client's actions and the live state the window shows.

    Create it on the GUI thread (its anchor object and jog timer live there)."""

    def __init__(self, client: ApiClient) -> None:
        self.client = client
        self.view: View = NoView()
        self.program: ChosenFile | None = None
        self.points: ChosenFile | None = None
        self.state: StateOut | None = None
        self.last_upload: UploadReport | None = None
        self.loaded: Loaded | None = None
        """What this client loaded (the file's name, its step -> line map)."""
        self.link: LinkStatus | None = None
        """None until the server has said."""
        self.feed_status = FeedStatus.CLOSED
        self.busy = ""
        self._anchor = QObject()
        self._commands = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-cmd")
        self._stopper = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-stop")
        self._reads = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-read")
        self._feed: LiveFeed | None = None
        self.hold = JogHold(self._send_live)
        self.workspaces: tuple[WorkspaceInfo, ...] = ()
        """The server's workspaces this user may load from (the IDE's), besides files."""
        self._closed = False

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def me(self) -> str:
        return self.client.user.username if self.client.user else ""

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

    def _tell(
        self,
        kind: NoticeKind,
        title: str,
        text: str,
        lines: tuple[str, ...] = (),
        fix: Fix | None = None,
        retry: Callable[[], object] | None = None,
    ) -> None:
        """Show a notice; with a ``fix`` the user can choose it (and then ``retry``)."""
        on_fix = partial(self.apply_fix, fix, retry) if fix is not None else None
        self.view.show_notice(Notice(kind, title, text, lines, fix), on_fix)

    def _set_busy(self, what: str) -> None:
        self.busy = what
        self.view.show_busy(what)

    def _submit(
        self,
        what: str,
        work: Callable[[], T],
        done: Callable[[T], None],
        failed_title: str,
        retry: Callable[[], object] | None = None,
    ) -> bool:
        """Run ``work`` on the command worker; ``done`` or a failure dialog on the GUI thread
        (offering the API's one-click fix, then ``retry``, where there is one)."""
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
                self._later(partial(self._failed, failed_title, exc, retry))
            else:
                self._later(partial(self._finished, done, result))

        self._commands.submit(job)
        return True

    def _finished(self, done: Callable[[T], None], result: T) -> None:
        self._set_busy("")
        done(result)

    def _failed(
        self, title: str, exc: BaseException, retry: Callable[[], object] | None = None
    ) -> None:
        self._set_busy("")
        self.view.show_progress(None)
        if not isinstance(exc, ApiError | ServerUnreachable):
            _log.error("unexpected failure in melfa desktop", exc_info=exc)
        text, lines = describe_failure(exc)
        self._log(f"{title}: {text}")
        self.view.show_status(f"{title}: {text}")
        fix = exc.fix if isinstance(exc, ApiError) else None
        fix = fix if fix in FIXES_OFFERED else None
        self._tell(NoticeKind.ERROR, title, text, lines, fix, retry)

    def apply_fix(self, fix: Fix, retry: Callable[[], object] | None = None) -> None:
        """Do the one-click fix the server offered (`melfa.protocol.advice.Fix`)."""
        if fix is Fix.SERVO_ON_RETRY:
            self._servo_on_and_retry(retry)
        elif fix is Fix.RESET_ALARM:
            self.reset_alarm()
        elif fix is Fix.LOAD_PROJECT:
            self.load()
        elif fix is Fix.STOP:
            self.stop()

    # --- live feed -----------------------------------------------------------------------

    def choose_target(self, target: str) -> None:
        """Drive ``target`` (``lab`` or ``mine``) from now on: the live feed follows it."""
        if target == self.client.target:
            return
        self.jog_release()
        self.client.target = target
        self._log(f"Now driving {TARGET_LABELS.get(target, target)}")
        if self._feed is not None:
            self._feed.close(timeout=1.0)
            self._feed = None
            self.start()

    def start(self) -> None:
        """Show the latest state and the workspaces now, then follow the WebSocket."""
        self._submit("Reading the state", self.client.state, self._on_state, "Could not read")
        self.refresh_workspaces()
        self._feed = LiveFeed(
            self.client.websocket_url,
            self.client.cookie_header(),
            lambda message: self._later(partial(self._on_live, message)),
            lambda status, detail: self._later(partial(self._on_feed, status, detail)),
        )
        self._feed.start()

    def refresh_workspaces(self) -> None:
        """List the workspaces again (off the GUI thread; not queued behind a command)."""
        if self._closed:
            return

        def job() -> None:
            try:
                found = self.client.workspaces()
            except (ApiError, ServerUnreachable):
                return  # an older server, or gone: files only (the feed says if it is gone)
            self._later(partial(self._on_workspaces, found))

        self._reads.submit(job)  # never on STOP's worker: a slow reply must not delay STOP

    def _on_workspaces(self, found: tuple[WorkspaceInfo, ...]) -> None:
        if found != self.workspaces:
            self.workspaces = found
            self.view.show_workspaces(found)

    def _send_live(self, message: Mapping[str, object]) -> bool:
        return self._feed is not None and self._feed.send(message)

    def _on_live(self, message: LiveMessage) -> None:
        if isinstance(message, StateOut):
            self._on_state(message)
        elif isinstance(message, LinkMessage):
            if message.status is not self.link:
                self._log(link_words(message.status))
            self._set_link(message.status, message.detail)
        elif isinstance(message, Hello):
            self._set_link(message.link, "")
        elif isinstance(message, CommandResultMessage):
            # This client logs its own commands when their answer comes; others' here.
            who = actor_name(message.actor)
            if who != self.me:
                result = "done" if message.ok else sentence(message.error)
                if message.command == Command.RUN and message.ok:
                    result = "started"
                self._log(f"{command_label(message.command)} by {who or 'the server'}: {result}")
        elif isinstance(message, ProgressMessage):
            if message.total and actor_name(message.actor) == self.me:
                text, percent = upload_progress(message.sent, message.total)
                self.view.show_status(text)
                self.view.show_progress(percent)
        elif isinstance(message, JogMessage):
            self._on_jog_changed(message)
        elif isinstance(message, JogHeartbeatAck):
            if self.hold.active:
                self._jog_ended("the server ended it")
        elif isinstance(message, ErrorMessage):
            self._on_refused(message)
        elif isinstance(message, QueueMessage):
            line, offered = queue_line(message, self.me)
            self.view.show_queue(line, offered)
            for step in message.steps:
                if step.user == self.me:
                    self._log(step.kind.words(step.user, step.by, step.position, step.seconds))

    def _on_jog_changed(self, message: JogMessage) -> None:
        if message.active or not self.hold.active:
            return
        if actor_name(message.actor) not in (self.me, None):
            return
        if message.end is None or message.end.expected or message.end is JogEnd.REFUSED:
            return  # our own release, or a refusal the error reply explains
        self._jog_ended(message.end.words(message.by))

    def _jog_ended(self, why: str) -> None:
        self.hold.ended()
        self.view.show_jog(None)
        self._log(f"Jog stopped: {why}")
        self.view.show_status(f"Jog stopped: {why}.")

    def _on_refused(self, message: ErrorMessage) -> None:
        if message.id is None or message.id != self.hold.start_id:
            return
        self.hold.ended()
        self.view.show_jog(None)
        text = sentence(message.error.message)
        self._log(f"Jog refused: {text}")
        self.view.show_status(f"Jog refused: {text}")
        fix = error_fix(message)
        fix = fix if fix in FIXES_OFFERED else None
        # With the servo fix, the servo comes on; the student presses the key again to move.
        self._tell(NoticeKind.ERROR, "Could not jog", text, fix=fix)

    def _on_state(self, state: StateOut) -> None:
        self.state = state
        if state.link is not self.link:
            self._set_link(state.link, "")
        if not state.busy:
            self.view.show_progress(None)
        self.view.show_state(state)

    def _set_link(self, status: LinkStatus | None, detail: str) -> None:
        self.link = status
        self.view.show_link(status, detail)

    def _on_feed(self, status: FeedStatus, detail: str) -> None:
        self.feed_status = status
        self.view.show_feed(status, detail)
        if status is not FeedStatus.CONNECTED and self.hold.active:
            self._jog_ended("the live connection dropped")
        if status is FeedStatus.REFUSED:
            self._log("Live updates stopped: the server refused them")
            self._tell(
                NoticeKind.ERROR,
                "Live updates stopped",
                "The server no longer accepts this session (signed out or expired). "
                "Close the window and sign in again.",
            )
        elif status is FeedStatus.DISCONNECTED:
            self.view.show_status("Live updates lost; reconnecting…")

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

    def choose_workspace(self, workspace_id: int | None) -> bool:
        """Load from a workspace of the server (the IDE's texts) instead of files; None goes
        back to files on this computer."""
        if workspace_id is None:
            if self.program is not None and self.program.workspace is not None:
                self.program = self.points = None
                self.view.show_files()
            return True
        return self._submit(
            "Opening the workspace",
            lambda: self._workspace_texts(workspace_id),
            self._on_workspace,
            "Could not open the workspace",
        )

    def _workspace_texts(self, workspace_id: int) -> tuple[ChosenFile, ChosenFile | None]:
        """Worker side: the workspace's latest program and points as chosen texts."""
        texts = self.client.workspace(workspace_id)
        return from_workspace(texts.id, texts.name, texts.program, texts.points)

    def _on_workspace(self, chosen: tuple[ChosenFile, ChosenFile | None]) -> None:
        self.program, self.points = chosen
        self.view.show_files()
        self.view.show_status(f"Chose {chosen[0].name}.")

    def _fresh(
        self, files: tuple[ChosenFile, ChosenFile | None]
    ) -> tuple[ChosenFile, ChosenFile | None]:
        """Worker side: a workspace's texts as they are on the server now (saved in the IDE
        since? load that); files were re-read on the GUI thread already."""
        program = files[0]
        if program.workspace_id is None:
            return files
        return self._workspace_texts(program.workspace_id)

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
        if self.program.workspace_id is not None:
            return self.program, self.points  # fetched again on the worker (`_fresh`)
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
        """Check the chosen texts (`/api/check`) and show the diagnostics; sends nothing."""
        files = self._reread()
        if files is None:
            return False

        def work() -> CheckResult:
            program, points = self._fresh(files)
            self._later(partial(self._took, program, points))
            return self.client.check(program.text, points.text if points else "")

        return self._submit("Checking", work, self._on_checked, "Check failed")

    def _took(self, program: ChosenFile, points: ChosenFile | None) -> None:
        """The texts a check or load used (a workspace's may have changed): show them."""
        if (program, points) != (self.program, self.points):
            self.program, self.points = program, points
            self.view.show_files()

    def _on_checked(self, result: CheckResult) -> None:
        self.view.show_check(result)
        errors = len(result.program_errors) + len(result.points_errors)
        others = len(result.program) + len(result.points) - errors
        self.view.show_status(
            f"Checked: {count(errors, 'error')}, {count(others, 'other finding')}."
        )

    def load(self) -> bool:
        """Check, then load program and points into the robot; errors refuse with a dialog."""
        files = self._reread()
        if files is None:
            return False

        def work() -> tuple[ChosenFile, ChosenFile | None, CheckResult | UploadReport]:
            program, points = self._fresh(files)
            self._later(partial(self._took, program, points))
            points_text = points.text if points else ""
            result = self.client.check(program.text, points_text)
            self._later(partial(self._show_check, result))
            if not result.ok:
                return program, points, result
            return program, points, self.client.load_project(program.text, points_text)

        return self._submit("Loading", work, self._on_loaded, "Load refused", self.load)

    def _on_loaded(
        self, loaded: tuple[ChosenFile, ChosenFile | None, CheckResult | UploadReport]
    ) -> None:
        program, points, outcome = loaded
        self.view.show_progress(None)
        if isinstance(outcome, CheckResult):
            bad = program.name if outcome.program_errors else (points.name if points else "")
            errors = len(outcome.program_errors) + len(outcome.points_errors)
            text = f"{bad} has {count(errors, 'error')}; nothing was sent to the robot."
            self._log(f"Load refused: {text}")
            self.view.show_status(f"Load refused: {text}")
            self._tell(NoticeKind.ERROR, "Program has errors", text, diagnostic_lines(outcome))
            return
        lines = len(program.text.splitlines())
        if program.workspace is not None:
            what = program.name
        else:
            what = program.name + (f" and {points.name}" if points else "")
        took = f", {outcome.seconds:.1f} s" if outcome.seconds >= 0.05 else ""
        self._log(f"Loaded {what} into the robot ({count(lines, 'line')}{took})")
        self.view.show_status(f"Loaded {what}: ready to run.")
        self.last_upload = outcome
        self.loaded = Loaded(program.name, dict(outcome.step_lines))
        if self.state is not None:
            self.view.show_state(self.state)  # the line of this file from now on

    def claim(self) -> bool:
        """Take the lab robot's arm the queue offers: the queued program loads and runs."""
        return self._submit(
            "Claiming the arm", self.client.claim, self._on_claimed, "Claim refused"
        )

    def _on_claimed(self, _: None) -> None:
        self._done("Your turn at the lab robot: your queued program loads and runs")

    def run(self) -> bool:
        """Start the program loaded in the robot."""
        return self._submit("Starting", self.client.run, self._on_ran, "Run refused", self.run)

    def _show_check(self, result: CheckResult) -> None:
        self.view.show_check(result)

    def _done(self, text: str) -> None:
        """A command's answer: the status bar keeps it until the next one, the log too."""
        self._log(text)
        self.view.show_status(text)

    def _on_ran(self, _: None) -> None:
        name = self.loaded.name if self.loaded else "the loaded program"
        self._done(f"Run: {name} started")

    def reset_alarm(self) -> bool:
        """Clear the controller's error (RSTALRM), e.g. after a refused instruction."""
        return self._submit(
            "Resetting the alarm",
            self.client.reset_alarm,
            lambda _: self._done("Reset alarm: done"),
            "Reset refused",
        )

    def servo(self, on: bool) -> bool:
        """Switch the servo on or off."""
        word = "on" if on else "off"
        return self._submit(
            f"Switching the servo {word}",
            lambda: self.client.servo(on),
            lambda _: self._done(f"Servo {word}"),
            "Servo refused",
        )

    def _servo_on_and_retry(self, retry: Callable[[], object] | None) -> bool:
        """The "Turn on and retry" fix: the L2000 the refused move left says only that the servo
        was off, which is being fixed, so it is cleared first (as the server does)."""

        def work() -> None:
            self.client.reset_alarm()
            self.client.servo(True)

        def done(_: None) -> None:
            self._done("Servo on")
            if retry is not None:
                retry()

        return self._submit("Switching the servo on", work, done, "Servo refused")

    def set_override(self, percent: int) -> bool:
        """Set the speed override (1–100 %)."""
        return self._submit(
            "Setting the speed",
            lambda: self.client.override(percent),
            lambda value: self._done(f"Speed override: {value} %"),
            "Speed refused",
        )

    def jog(self, frame: str, axis: int, direction: int) -> bool:
        """One jog step (REST `jog-step`): the *One step* mode."""
        label = jog_label(frame, axis, direction)
        return self._submit(
            "Jogging one step",
            lambda: self.client.jog_step(frame, axis, direction),
            lambda _: self._done(f"Jog step {label}: done"),
            "Jog refused",
        )

    def jog_press(self, frame: str, axis: int, direction: int) -> bool:
        """A jog key went down: move while it is held (hold-to-move over the WebSocket)."""
        key = JogKey(frame, axis, direction)
        if self.hold.held == key:
            return True
        if self.feed_status is not FeedStatus.CONNECTED or not self.hold.press(key):
            self.view.show_status("Jog needs the live connection; it is reconnecting.")
            return False
        self._log(f"Jog {jog_label(frame, axis, direction)} (held)")
        self.view.show_jog(key)
        return True

    def jog_release(self) -> None:
        """The jog key came up (or the window lost the keyboard): stop now."""
        if self.hold.release():
            self.view.show_jog(None)

    def exec_statement(self, text: str) -> bool:
        """Send one MELFA BASIC statement (EXEC)."""
        statement = text.strip()
        if not statement:
            self.view.show_status("Type an instruction first, e.g. MOV P1 or HOPEN 1.")
            return False
        return self._submit(
            "Sending the instruction",
            lambda: self.client.exec_statement(statement),
            lambda _: self._done(f"Instruction {statement}: done"),
            "Instruction refused",
            partial(self.exec_statement, statement),
        )

    def stop(self) -> None:
        """STOP: on its own worker, never queued behind a command; always allowed."""
        if self._closed:
            return
        self.jog_release()
        self._log("STOP")
        self.view.show_status("STOP sent…")

        def job() -> None:
            try:
                self.client.stop()
            except Exception as exc:
                self._later(partial(self._failed_stop, exc))
            else:
                self._later(partial(self._done, "STOP: the robot stopped"))

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
        """Stop any jog, close the feed, drop queued work, sign out (best effort). Idempotent."""
        if self._closed:
            return
        self.jog_release()
        self._closed = True
        if self._feed is not None:
            self._feed.close()
        self._commands.shutdown(wait=False, cancel_futures=True)
        self._stopper.shutdown(wait=False, cancel_futures=True)
        self._reads.shutdown(wait=False, cancel_futures=True)
        with contextlib.suppress(ApiError, ServerUnreachable):
            self.client.logout()


__all__ = ["FIXES_OFFERED", "Presenter"]
