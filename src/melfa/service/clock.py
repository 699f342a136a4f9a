"""The service's time: every wait in the service goes through a `Clock`.

`Clock` is real time (``time.monotonic``, ``asyncio.sleep``, ``Condition.wait``).
`FakeClock` is time the tests own: it stands still while anything can still happen without
it (the worker thread working, the event loop holding ready callbacks, a STOP on its way)
and jumps to the next deadline only when everything waits for time. A test that says
``await clock.sleep(0.6)`` lets 0.6 s of the service's life pass in as much wall time as
the work in it takes; a test asserts on `FakeClock.now`, never on how long it waited.

The worker thread waits with `Clock.wait` on its condition and is woken with
`Clock.notify`; it runs inside `Clock.thread` so a fake clock knows whom to wait for.
A thread that must let time pass (a paced line) calls `Clock.pause`.
"""

from __future__ import annotations

import asyncio
import contextlib
import heapq
import itertools
import threading
import time
from collections.abc import AsyncIterator, Callable, Iterator
from dataclasses import dataclass, field


class Clock:
    """Real time: ``now`` from ``time.monotonic`` (or the function given)."""

    def __init__(self, now: Callable[[], float] = time.monotonic) -> None:
        self._now = now

    def now(self) -> float:
        """Seconds on a clock that never goes back (any origin)."""
        return self._now()

    async def sleep(self, seconds: float) -> None:
        """Let ``seconds`` pass (on the event loop)."""
        await asyncio.sleep(seconds)

    def wait(self, cond: threading.Condition, timeout: float | None) -> bool:
        """In a thread holding ``cond``: wait until `notify` or ``timeout`` seconds have
        passed; True when notified."""
        return cond.wait(timeout)

    def notify(self, cond: threading.Condition) -> None:
        """Wake every `wait` on ``cond`` (the caller holds it)."""
        cond.notify_all()

    def pause(self, seconds: float) -> None:
        """In a thread: let ``seconds`` pass (a paced line's character times)."""
        if seconds > 0:
            time.sleep(seconds)

    @contextlib.contextmanager
    def thread(self) -> Iterator[None]:
        """Around the body of a thread that waits on this clock."""
        yield


@dataclass(eq=False)
class _ThreadWait:
    cond: threading.Condition
    deadline: float
    asleep: bool = True
    notified: bool = False


@dataclass(order=True)
class _Sleep:
    deadline: float
    seq: int
    future: asyncio.Future[None] = field(compare=False)


class FakeClock(Clock):
    """Time that passes only when everything waits for it (tests).

    Start `run` (or use ``async with clock.running():``) on the event loop of the service
    under test: it is the only thing that moves time on.

    >>> async def demo() -> float:
    ...     clock = FakeClock()
    ...     async with clock.running():
    ...         await clock.sleep(2.5)
    ...     return clock.now()
    >>> asyncio.run(demo())
    2.5
    """

    SPINS = 8
    """Event-loop turns with nothing new before time may jump."""
    STUCK_S = 30.0
    """Real seconds a thread may work without waiting before the clock gives up on it."""

    def __init__(self, start: float = 0.0) -> None:
        super().__init__()
        self._t = start
        self._lock = threading.Condition()
        self._waits: list[_ThreadWait] = []
        self._sleeps: list[_Sleep] = []
        self._seq = itertools.count()
        self._threads = 0
        self._activity = 0
        """Counts everything that happens; time may jump only while it stands still."""
        self._driver: asyncio.AbstractEventLoop | None = None
        self._wake: asyncio.Event | None = None

    def now(self) -> float:
        with self._lock:
            return self._t

    def advance_to(self, when: float) -> None:
        """Move time on to ``when`` (never back) and wake whatever is due. `run` does this;
        a test without `run` may call it itself."""
        with self._lock:
            self._t = max(self._t, when)
            due = [w for w in self._waits if w.asleep and w.deadline <= self._t]
            sleeps = []
            while self._sleeps and self._sleeps[0].deadline <= self._t:
                sleeps.append(heapq.heappop(self._sleeps))
            self._activity += 1
        for w in due:
            with w.cond:
                with self._lock:
                    w.asleep = False
                w.cond.notify_all()
        for s in sleeps:
            if not s.future.done():
                s.future.get_loop().call_soon_threadsafe(_resolve, s.future)

    async def sleep(self, seconds: float) -> None:
        if seconds <= 0:
            await asyncio.sleep(0)
            return
        future: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        with self._lock:
            heapq.heappush(self._sleeps, _Sleep(self._t + seconds, next(self._seq), future))
            self._activity += 1
        self._kick()
        await future

    def wait(self, cond: threading.Condition, timeout: float | None) -> bool:
        with self._lock:
            deadline = float("inf") if timeout is None else self._t + max(0.0, timeout)
            entry = _ThreadWait(cond, deadline)
            if deadline <= self._t:
                return False
            self._waits.append(entry)
            self._activity += 1
        self._kick()
        try:
            while True:
                with self._lock:
                    if not entry.asleep:
                        return entry.notified
                cond.wait()
        finally:
            with self._lock:
                self._waits.remove(entry)
                entry.asleep = False
                self._activity += 1

    def pause(self, seconds: float) -> None:
        cond = threading.Condition()
        with cond:
            self.wait(cond, seconds)

    def notify(self, cond: threading.Condition) -> None:
        with self._lock:
            for w in self._waits:
                if w.cond is cond and w.asleep:
                    w.asleep = False
                    w.notified = True
            self._activity += 1
        cond.notify_all()

    @contextlib.contextmanager
    def thread(self) -> Iterator[None]:
        with self._lock:
            self._threads += 1
            self._activity += 1
        try:
            yield
        finally:
            with self._lock:
                self._threads -= 1
                self._activity += 1
            self._kick()

    # ------------------------------------------------------------------ the driver

    def _kick(self) -> None:
        """Something may now wait for time: wake the driver if it sleeps."""
        loop, wake = self._driver, self._wake
        if loop is not None and wake is not None:
            with contextlib.suppress(RuntimeError):
                loop.call_soon_threadsafe(wake.set)

    def _threads_waiting(self) -> bool:
        """Every clock thread waits on this clock."""
        asleep = sum(1 for w in self._waits if w.asleep)
        return asleep >= self._threads

    def _next_deadline(self) -> float | None:
        with self._lock:
            times = [w.deadline for w in self._waits if w.asleep]
            times += [s.deadline for s in self._sleeps if not s.future.done()]
            finite = [t for t in times if t != float("inf")]
            return min(finite) if finite else None

    async def _settled(self) -> None:
        """Until every clock thread waits on this clock (the loop runs
        on meanwhile: the test and the service go on while the worker works)."""
        wake = self._wake
        assert wake is not None, "the driver runs inside run()"
        while True:
            wake.clear()
            with self._lock:
                if self._threads_waiting():
                    return
            try:  # asyncio.timeout: a cancel that meets a wake-up still cancels
                async with asyncio.timeout(self.STUCK_S):
                    await wake.wait()
            except TimeoutError:
                raise RuntimeError("FakeClock: a thread kept working without waiting") from None

    async def idle(self) -> None:
        """Return when nothing can happen any more without time passing."""
        while True:
            await self._settled()
            with self._lock:
                before = self._activity
            for _ in range(self.SPINS):
                await asyncio.sleep(0)
            with self._lock:
                if self._activity == before and self._threads_waiting():
                    return

    async def run(self) -> None:
        """Move time on whenever everything waits for it (run as a task; cancel it)."""
        self._driver = asyncio.get_running_loop()
        self._wake = wake = asyncio.Event()
        try:
            while True:
                await self.idle()
                when = self._next_deadline()
                if when is not None:
                    self.advance_to(when)
                    continue
                wake.clear()  # nothing waits for time: sleep until something does
                if self._next_deadline() is None:
                    await wake.wait()
        finally:
            self._driver = self._wake = None

    @contextlib.asynccontextmanager
    async def running(self) -> AsyncIterator[FakeClock]:
        task = asyncio.create_task(self.run(), name="fake-clock")
        try:
            yield self
        finally:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task


def _resolve(future: asyncio.Future[None]) -> None:
    if not future.done():
        future.set_result(None)


__all__ = ["Clock", "FakeClock"]
