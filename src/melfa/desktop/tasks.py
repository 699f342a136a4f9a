"""Work off the GUI thread, its answer back on it: the desktop client's three workers.

A slow controller (an upload at 9600 baud, a `run` that answers when the controller did)
must never freeze the window, and STOP must never wait behind it. So commands go one at a
time through one worker, STOP has a worker of its own, and reads that nobody waits for (the
workspace list) a third. What a job returns, or what it raised, comes back to the GUI thread
by a zero-time `QTimer.singleShot` on an anchor object living there. Kept apart from the
presenter, which decides what each answer means; here is only where work runs.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import TypeVar

from PySide6.QtCore import QObject, QTimer

T = TypeVar("T")


class Tasks:
    """The workers of one signed-in client. Create it on the GUI thread (its anchor lives
    there); once closed, queued work is dropped and no answer is delivered."""

    def __init__(self) -> None:
        self._anchor = QObject()
        self._commands = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-cmd")
        self._stopper = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-stop")
        self._reads = ThreadPoolExecutor(1, thread_name_prefix="melfa-desktop-read")
        self._closed = False

    @property
    def closed(self) -> bool:
        return self._closed

    def later(self, call: Callable[[], None]) -> None:
        """Run ``call`` on the GUI thread (safe from any thread); dropped once closed."""
        if not self._closed:
            QTimer.singleShot(0, self._anchor, partial(self._deliver, call))

    def _deliver(self, call: Callable[[], None]) -> None:
        if not self._closed:
            call()

    def command(
        self, work: Callable[[], T], done: Callable[[T], None], failed: Callable[[Exception], None]
    ) -> None:
        """Run ``work`` on the command worker, after the commands before it."""
        self._run(self._commands, work, done, failed)

    def stop(
        self, work: Callable[[], T], done: Callable[[T], None], failed: Callable[[Exception], None]
    ) -> None:
        """Run ``work`` on STOP's own worker: never queued behind a command."""
        self._run(self._stopper, work, done, failed)

    def read(
        self, work: Callable[[], T], done: Callable[[T], None], failed: Callable[[Exception], None]
    ) -> None:
        """Run ``work`` on the read worker: neither behind a command nor delaying STOP."""
        self._run(self._reads, work, done, failed)

    def _run(
        self,
        pool: ThreadPoolExecutor,
        work: Callable[[], T],
        done: Callable[[T], None],
        failed: Callable[[Exception], None],
    ) -> None:
        """``done(result)`` or ``failed(exception)`` on the GUI thread."""
        if self._closed:
            return

        def job() -> None:
            try:
                result = work()
            except Exception as exc:
                self.later(partial(failed, exc))
            else:
                self.later(partial(done, result))

        pool.submit(job)

    def close(self) -> None:
        """Deliver nothing more and drop queued work (a running job ends on its own)."""
        self._closed = True
        self._commands.shutdown(wait=False, cancel_futures=True)
        self._stopper.shutdown(wait=False, cancel_futures=True)
        self._reads.shutdown(wait=False, cancel_futures=True)


__all__ = ["Tasks"]
