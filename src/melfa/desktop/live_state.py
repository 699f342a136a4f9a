"""The robot as the live feed (`/api/ws`) tells it: its state, the link, the feed's own
status, the lab robot's queue, others' commands, and the hold-to-move jog that rides on it.

Kept apart from the presenter because it is the part the server drives, not the user:
messages arrive on the feed's thread, are handed to the GUI thread (`Tasks.later`) and
change what the window shows. The presenter's commands read the state kept here, and the
user's jog keys come here through the presenter, since a held jog lives and ends with the
feed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import partial
from typing import Protocol

from melfa.desktop.api import ApiClient
from melfa.desktop.dialogs import NoticeKind
from melfa.desktop.hold import JogHold, JogKey
from melfa.desktop.live import FeedStatus, LiveFeed
from melfa.desktop.messages import LiveMessage, actor_name, error_fix
from melfa.desktop.tasks import Tasks
from melfa.desktop.view import NoView, View
from melfa.desktop.words import jog_label, link_words, queue_line, sentence, upload_progress
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
from melfa.vocab.jog import JOG_END_UNKNOWN, JogEnd
from melfa.vocab.link import LinkStatus


class Tell(Protocol):
    """Show a notice, offering ``fix`` where the client can do it (`Presenter._tell`)."""

    def __call__(
        self,
        kind: NoticeKind,
        title: str,
        text: str,
        lines: tuple[str, ...] = (),
        fix: Fix | None = None,
    ) -> None: ...


class LiveState:
    """One signed-in client's live feed and what it last said; on the GUI thread."""

    def __init__(
        self, client: ApiClient, tasks: Tasks, log: Callable[[str], None], tell: Tell
    ) -> None:
        self.client = client
        self.view: View = NoView()
        self.state: StateOut | None = None
        self.link: LinkStatus | None = None
        """None until the server has said."""
        self.queued = False
        """Someone waits in the lab robot's queue: only the queue gives control."""
        self.feed_status = FeedStatus.CLOSED
        self.hold = JogHold(self._send)
        self._feed: LiveFeed | None = None
        self._tasks = tasks
        self._log = log
        self._tell = tell

    @property
    def me(self) -> str:
        return self.client.user.username if self.client.user else ""

    def open(self) -> None:
        """Follow the WebSocket of the client's target from now on."""
        self._feed = LiveFeed(
            self.client.websocket_url,
            self.client.cookie_header(),
            lambda message: self._tasks.later(partial(self.on_message, message)),
            lambda status, detail: self._tasks.later(partial(self._on_feed, status, detail)),
        )
        self._feed.start()

    def close(self, timeout: float = 5.0) -> bool:
        """Close the feed; whether one was open."""
        if self._feed is None:
            return False
        self._feed.close(timeout=timeout)
        self._feed = None
        return True

    def _send(self, message: Mapping[str, object]) -> bool:
        return self._feed is not None and self._feed.send(message)

    # --- the jog keys --------------------------------------------------------------------

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
        """The jog key came up (or the window lost the keyboard): stop now, and say so in
        place of "Jogging …: let go to stop"."""
        if self.hold.release():
            self.view.show_jog(None)
            self.view.show_status(_stopped(JogEnd.RELEASED.words()) + ".")

    # --- what the feed says --------------------------------------------------------------

    def on_message(self, message: LiveMessage) -> None:
        if isinstance(message, StateOut):
            self.on_state(message)
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
                self._jog_ended(JOG_END_UNKNOWN)
        elif isinstance(message, ErrorMessage):
            self._on_refused(message)
        elif isinstance(message, QueueMessage):
            self.queued = message.active
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
        self._log(_stopped(why))
        self.view.show_status(_stopped(why) + ".")

    def _on_refused(self, message: ErrorMessage) -> None:
        if message.id is None or message.id != self.hold.start_id:
            return
        self.hold.ended()
        self.view.show_jog(None)
        text = sentence(message.error.message)
        self._log(f"Jog refused: {text}")
        self.view.show_status(f"Jog refused: {text}")
        # With the servo fix, the servo comes on; the student presses the key again to move.
        self._tell(NoticeKind.ERROR, "Could not jog", text, fix=error_fix(message))

    def on_state(self, state: StateOut) -> None:
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


def _stopped(why: str) -> str:
    """What the status bar and the log say when a jog ended (``why``: `JogEnd.words`)."""
    return f"Jog stopped: {why}"


__all__ = ["LiveState", "Tell"]
