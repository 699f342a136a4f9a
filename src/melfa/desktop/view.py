"""What the presenter asks a window to show: the `View` protocol (the window is one; tests
may pass another) and `NoView`, the presenter's view before a window is attached."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

from melfa.desktop.api import CheckResult, WorkspaceInfo
from melfa.desktop.dialogs import Notice
from melfa.desktop.hold import JogKey
from melfa.desktop.live import FeedStatus
from melfa.live.messages import StateOut
from melfa.vocab.link import LinkStatus


class View(Protocol):
    """What the presenter asks the window to show (always on the GUI thread)."""

    def show_state(self, state: StateOut) -> None: ...
    def show_link(self, status: LinkStatus | None, detail: str) -> None: ...
    def show_feed(self, status: FeedStatus, detail: str) -> None: ...
    def show_busy(self, what: str) -> None: ...
    def show_files(self) -> None: ...
    def show_check(self, result: CheckResult) -> None: ...
    def show_notice(self, notice: Notice, on_fix: Callable[[], object] | None = None) -> None: ...
    def append_log(self, line: str) -> None: ...
    def show_status(self, text: str) -> None: ...
    def show_progress(self, percent: int | None) -> None: ...
    def show_jog(self, held: JogKey | None) -> None: ...
    def show_workspaces(self, workspaces: tuple[WorkspaceInfo, ...]) -> None: ...
    def show_queue(self, line: str, offered: bool) -> None: ...


class NoView:
    """Shows nothing: the presenter before a window is attached."""

    def show_state(self, state: StateOut) -> None:
        pass

    def show_link(self, status: LinkStatus | None, detail: str) -> None:
        pass

    def show_feed(self, status: FeedStatus, detail: str) -> None:
        pass

    def show_busy(self, what: str) -> None:
        pass

    def show_files(self) -> None:
        pass

    def show_check(self, result: CheckResult) -> None:
        pass

    def show_notice(self, notice: Notice, on_fix: Callable[[], object] | None = None) -> None:
        pass

    def append_log(self, line: str) -> None:
        pass

    def show_status(self, text: str) -> None:
        pass

    def show_progress(self, percent: int | None) -> None:
        pass

    def show_jog(self, held: JogKey | None) -> None:
        pass

    def show_workspaces(self, workspaces: tuple[WorkspaceInfo, ...]) -> None:
        pass

    def show_queue(self, line: str, offered: bool) -> None:
        pass


__all__ = ["NoView", "View"]
