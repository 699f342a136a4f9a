"""Between the widgets and the API: what each button means, done off the GUI thread.

Every API call runs on a worker (`tasks.Tasks`: commands one at a time, STOP on a worker of
its own, so it is never queued behind a load); its answer or failure comes back to the GUI
thread and goes to the `View`. What the live feed says, and the held jog that rides on it,
is `live_state.LiveState`; here are the user's intents: choosing files, checking, loading,
running, the servo, the speed, one instruction, STOP, and the one-click fixes.

The presenter tells its view what to show through plain method calls (a `View`), not Qt
signals, so it can be tested with any view and stays free of Qt's threading rules.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable
from datetime import datetime
from functools import partial
from pathlib import Path
from typing import TypeVar

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
from melfa.desktop.live_state import LiveState
from melfa.desktop.messages import offered_fix
from melfa.desktop.tasks import Tasks
from melfa.desktop.view import NoView, View
from melfa.desktop.words import (
    Loaded,
    count,
    describe_failure,
    diagnostic_lines,
    jog_label,
)
from melfa.protocol.advice import Fix
from melfa.vocab.queue import QUEUE_WORDS

_log = logging.getLogger(__name__)

T = TypeVar("T")


def _log_if_unexpected(exc: BaseException) -> None:
    """A failure that is neither the API's answer nor the network is a bug in this client:
    its traceback goes to the terminal (the user is told in words, `describe_failure`)."""
    if not isinstance(exc, ApiError | ServerUnreachable):
        _log.error("unexpected failure in melfa desktop", exc_info=exc)


class Presenter:
    """One signed-in client's actions; the live state the window shows is `live`.

    Create it on the GUI thread (its workers' anchor and the jog timer live there)."""

    def __init__(self, client: ApiClient) -> None:
        self.client = client
        self.view: View = NoView()
        self.program: ChosenFile | None = None
        self.points: ChosenFile | None = None
        self.last_upload: UploadReport | None = None
        self.loaded: Loaded | None = None
        """What this client loaded (the file's name, its step -> line map)."""
        self.busy = ""
        self.tasks = Tasks()
        self.live = LiveState(client, self.tasks, self._log, self._tell)
        self.workspaces: tuple[WorkspaceInfo, ...] = ()
        """The server's workspaces this user may load from (the IDE's), besides files."""

    @property
    def closed(self) -> bool:
        return self.tasks.closed

    @property
    def me(self) -> str:
        return self.live.me

    def attach(self, view: View) -> None:
        self.view = self.live.view = view

    # --- plumbing ------------------------------------------------------------------------

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
        """Show a notice; with a ``fix`` this client can do (`messages.offered_fix`) the
        user can choose it (and then ``retry``)."""
        fix = offered_fix(fix)
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
        if self.tasks.closed:
            return False
        if self.busy:
            self.view.show_status(f"Still {self.busy.lower()}; wait for it or press STOP.")
            return False
        self._set_busy(what)
        self.tasks.command(
            work, partial(self._finished, done), partial(self._failed, failed_title, retry=retry)
        )
        return True

    def _finished(self, done: Callable[[T], None], result: T) -> None:
        self._set_busy("")
        done(result)

    def _failed(
        self, title: str, exc: BaseException, retry: Callable[[], object] | None = None
    ) -> None:
        self._set_busy("")
        self.view.show_progress(None)
        _log_if_unexpected(exc)
        text, lines = describe_failure(exc)
        self._log(f"{title}: {text}")
        self.view.show_status(f"{title}: {text}")
        fix = exc.fix if isinstance(exc, ApiError) else None
        self._tell(NoticeKind.ERROR, title, text, lines, fix, retry)

    def apply_fix(self, fix: Fix, retry: Callable[[], object] | None = None) -> None:
        """Do the one-click fix the server offered (`melfa.protocol.advice.Fix`): one of
        `messages.FIXES_OFFERED`, each done here."""
        if fix is Fix.SERVO_ON_RETRY:
            self._servo_on_and_retry(retry)
        elif fix is Fix.RESET_ALARM:
            self.reset_alarm()
        elif fix is Fix.LOAD_PROJECT:
            self.load()
        elif fix is Fix.STOP:
            self.stop()

    # --- the robot to follow -------------------------------------------------------------

    def choose_target(self, target: str) -> None:
        """Drive ``target`` (``lab`` or ``mine``) from now on: the live feed follows it."""
        if target == self.client.target:
            return
        self.jog_release()
        self.client.target = target
        self._log(f"Now driving {TARGET_LABELS.get(target, target)}")
        if self.live.close(timeout=1.0):
            self.start()

    def start(self) -> None:
        """Show the latest state and the workspaces now, then follow the WebSocket."""
        self._submit("Reading the state", self.client.state, self.live.on_state, "Could not read")
        self.refresh_workspaces()
        self.live.open()

    def refresh_workspaces(self) -> None:
        """List the workspaces again (off the GUI thread; not queued behind a command)."""
        # Never on STOP's worker: a slow reply must not delay STOP. Failed (an older server,
        # or gone): files only, and the feed says if the server is gone.
        self.tasks.read(self.client.workspaces, self._on_workspaces, _log_if_unexpected)

    def _on_workspaces(self, found: tuple[WorkspaceInfo, ...]) -> None:
        if found != self.workspaces:
            self.workspaces = found
            self.view.show_workspaces(found)

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
            self.tasks.later(partial(self._took, program, points))
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
            self.tasks.later(partial(self._took, program, points))
            points_text = points.text if points else ""
            result = self.client.check(program.text, points_text)
            self.tasks.later(partial(self._show_check, result))
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
        if self.live.state is not None:
            self.view.show_state(self.live.state)  # the line of this file from now on

    def claim(self) -> bool:
        """Take the lab robot's arm the queue offers: the queued program loads and runs."""
        w = QUEUE_WORDS
        return self._submit(w.claiming, self.client.claim, self._on_claimed, w.claim_failed)

    def _on_claimed(self, _: None) -> None:
        self._done(QUEUE_WORDS.claimed)

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
        return self.live.jog_press(frame, axis, direction)

    def jog_release(self) -> None:
        """The jog key came up (or the window lost the keyboard): stop now."""
        self.live.jog_release()

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
        if self.tasks.closed:
            return
        self.jog_release()
        self._log("STOP")
        self.view.show_status("STOP sent…")
        self.tasks.stop(
            self.client.stop, lambda _: self._done("STOP: the robot stopped"), self._failed_stop
        )

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
        if self.tasks.closed:
            return
        self.jog_release()
        self.tasks.close()
        self.live.close()
        with contextlib.suppress(ApiError, ServerUnreachable):
            self.client.logout()


__all__ = ["Presenter"]
