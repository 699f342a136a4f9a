"""Publish once, deliver to any number of subscribers, never let one slow the others.

Each `Subscription` holds a small bounded queue. A new `StateSnapshot` *replaces* the one
still waiting in a subscriber's queue (a stale snapshot is worthless), as does a newer
`UploadProgress` of the same command; other events queue up to ``maxlen`` and then the
oldest is dropped (counted in ``dropped``). Publishing is O(subscribers) with no await, so
the poller never waits for a reader. All of it runs on the event loop's thread.
"""

from __future__ import annotations

import asyncio
from collections import deque
from collections.abc import Callable, Hashable
from dataclasses import dataclass

from melfa.service.errors import ServiceClosed
from melfa.service.events import Event, StateSnapshot, UploadProgress

DEFAULT_MAXLEN = 256


def coalesce_key(event: Event) -> Hashable | None:
    """Events that supersede their predecessors share a key."""
    if isinstance(event, StateSnapshot):
        return "state"
    if isinstance(event, UploadProgress):
        return ("progress", event.command_id)
    return None


@dataclass
class _Cell:
    event: Event
    key: Hashable | None


class Subscription:
    """An async iterator of events. ``async for event in sub`` ends when the service closes
    or `close` is called."""

    def __init__(
        self,
        bus: EventBus,
        kinds: tuple[type[Event], ...] | None,
        maxlen: int,
    ) -> None:
        self._bus = bus
        self.kinds = kinds
        self.maxlen = maxlen
        self._queue: deque[_Cell] = deque()
        self._waiting: dict[Hashable, _Cell] = {}
        self._wakeup = asyncio.Event()
        self.closed = False
        self.dropped = 0
        """Events dropped because this subscriber fell behind (snapshots replaced in place
        are not counted: they are superseded, not lost)."""
        self.replaced = 0

    @property
    def wants_state(self) -> bool:
        return self.kinds is None or any(issubclass(StateSnapshot, k) for k in self.kinds)

    def wants(self, event: Event) -> bool:
        return self.kinds is None or isinstance(event, self.kinds)

    def _put(self, event: Event) -> None:
        key = coalesce_key(event)
        if key is not None and key in self._waiting:
            self._waiting[key].event = event
            self.replaced += 1
        else:
            if len(self._queue) >= self.maxlen:
                old = self._queue.popleft()
                if old.key is not None and self._waiting.get(old.key) is old:
                    del self._waiting[old.key]
                self.dropped += 1
            cell = _Cell(event, key)
            self._queue.append(cell)
            if key is not None:
                self._waiting[key] = cell
        self._wakeup.set()

    def get_nowait(self) -> Event | None:
        """The next event, or None when none is waiting."""
        if not self._queue:
            return None
        cell = self._queue.popleft()
        if cell.key is not None and self._waiting.get(cell.key) is cell:
            del self._waiting[cell.key]
        if not self._queue:
            self._wakeup.clear()
        return cell.event

    async def get(self) -> Event:
        """Wait for the next event; `ServiceClosed` once closed and drained."""
        while True:
            event = self.get_nowait()
            if event is not None:
                return event
            if self.closed:
                raise ServiceClosed("subscription closed")
            self._wakeup.clear()
            await self._wakeup.wait()

    async def get_within(self, seconds: float | None) -> Event | None:
        """The next event, or None when none comes within ``seconds`` (None: no limit).
        Cancelling the caller always ends it, even when an event arrives in the same
        moment: Python 3.11's `asyncio.wait_for` then returns the event and drops the
        cancellation, and a socket's pump that got a snapshot 20 times a second ran on
        after its socket had closed (the server's Ctrl-C waited 3 s for it)."""
        try:
            async with asyncio.timeout(seconds):
                return await self.get()
        except TimeoutError:
            return None

    def pending(self) -> int:
        return len(self._queue)

    def close(self) -> None:
        """Stop receiving (safe twice)."""
        if not self.closed:
            self.closed = True
            self._bus._remove(self)
            self._wakeup.set()

    def __aiter__(self) -> Subscription:
        return self

    async def __anext__(self) -> Event:
        try:
            return await self.get()
        except ServiceClosed:
            raise StopAsyncIteration from None

    def __enter__(self) -> Subscription:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class EventBus:
    """Fan-out of events to subscriptions (loop thread only)."""

    def __init__(self, on_change: Callable[[], None] | None = None) -> None:
        self._subs: list[Subscription] = []
        self._on_change = on_change
        self.published = 0

    def subscribe(
        self, kinds: tuple[type[Event], ...] | None = None, maxlen: int = DEFAULT_MAXLEN
    ) -> Subscription:
        if maxlen < 1:
            raise ValueError("a subscription needs room for at least one event")
        sub = Subscription(self, kinds, maxlen)
        self._subs.append(sub)
        if self._on_change is not None:
            self._on_change()
        return sub

    def _remove(self, sub: Subscription) -> None:
        if sub in self._subs:
            self._subs.remove(sub)
            if self._on_change is not None:
                self._on_change()

    @property
    def state_listeners(self) -> int:
        return sum(1 for s in self._subs if s.wants_state)

    @property
    def subscribers(self) -> int:
        return len(self._subs)

    def publish(self, event: Event) -> None:
        self.published += 1
        for sub in list(self._subs):
            if sub.wants(event):
                sub._put(event)

    def close(self) -> None:
        for sub in list(self._subs):
            sub.close()


__all__ = ["DEFAULT_MAXLEN", "EventBus", "Subscription", "coalesce_key"]
