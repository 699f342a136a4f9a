"""Shared helpers for the service tests: a controller that records what reached it, and
services on in-memory links to it that live on the test's `FakeClock`.

`run` gives each test a fresh fake clock and moves it on whenever the service, the
simulator and the test all wait for time (`melfa.service.clock`): a test lets time pass
with ``await clock().sleep(s)`` and asserts on ``clock().now()``, never on wall time."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import dataclass
from typing import Any, TypeVar

from melfa.link import Link, LinkSettings, MemoryLink, PacedLink
from melfa.service import Actor, RobotService, Role, ServiceConfig
from melfa.service.clock import FakeClock
from melfa.sim import VirtualController, open_sim_link

T = TypeVar("T")

ANN = Actor("ann", Role.STUDENT, "s-ann")
BOB = Actor("bob", Role.STUDENT, "s-bob")
OLGA = Actor("olga", Role.OBSERVER, "s-olga")
IRIS = Actor("iris", Role.INSTRUCTOR, "s-iris")

LINK = LinkSettings(timeout=3.0)


@dataclass(frozen=True)
class Seen:
    """One request as the controller received it: its time and its text."""

    now: float
    command: str


class RecordingController(VirtualController):
    """The virtual controller, noting every request line it answers (controller side)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.seen: list[Seen] = []
        self._seen_lock = threading.Lock()

    def handle(self, request: bytes | str, now: float) -> bytes:
        text = request.decode("latin-1") if isinstance(request, bytes) else request
        with self._seen_lock:
            self.seen.append(Seen(now, text.strip("\r")))
        return super().handle(request, now)

    def commands(self, *, skip_polls: bool = False) -> list[str]:
        """Request texts without the robot;slot prefix kept (it matters: slot 9 EMDAT)."""
        polls = ("JPOSF", "PPOSF", "STATE", "HNDSTS", "ERRORMES")
        with self._seen_lock:
            items = [s.command for s in self.seen]
        if skip_polls:
            items = [c for c in items if c.split(";", 2)[-1].split("=")[0] not in polls]
        return items


class Links:
    """A link factory that remembers what it opened (to pull plugs in tests)."""

    def __init__(
        self, controller: VirtualController, clock: FakeClock, *, pace: bool = False
    ) -> None:
        self.controller = controller
        self.clock = clock
        self.pace = pace
        self.opened: list[Link] = []
        self.memory: list[MemoryLink] = []

    def __call__(self) -> Link:
        link: Link = open_sim_link(LINK, controller=self.controller, clock=self.clock.now)
        assert isinstance(link, MemoryLink)
        self.memory.append(link)
        if self.pace:
            link = PacedLink(link, now=self.clock.now, sleep=self.clock.pause)
        self.opened.append(link)
        return link


_clock: FakeClock | None = None


def clock() -> FakeClock:
    """The running test's clock (inside `run`)."""
    assert _clock is not None, "only inside run()"
    return _clock


def make_service(
    controller: VirtualController, *, pace: bool = False, **config: Any
) -> tuple[RobotService, Links]:
    """A service on the test's clock, its controller's time the same clock."""
    links = Links(controller, clock(), pace=pace)
    return RobotService(links, config=ServiceConfig(**config), clock=clock()), links


def run(coro: Coroutine[Any, Any, T], timeout: float = 60.0) -> T:
    """Run a test coroutine on a fresh `FakeClock`; the (real) timeout only guards
    against hangs."""
    global _clock
    _clock = FakeClock()

    async def guarded() -> T:
        assert _clock is not None
        async with _clock.running():
            return await asyncio.wait_for(coro, timeout)

    try:
        return asyncio.run(guarded())
    finally:
        _clock = None


async def until(predicate: Callable[[], bool], timeout: float = 10.0) -> bool:
    """Wait, in the test's time, until ``predicate`` holds; False after ``timeout``."""
    end = clock().now() + timeout
    while clock().now() < end:
        if predicate():
            return True
        await clock().sleep(0.01)
    return predicate()


async def gather_all(*aws: Awaitable[Any]) -> list[Any]:
    return list(await asyncio.gather(*aws, return_exceptions=True))
