"""Shared helpers for the service tests: a controller that records what reached it, and
services on in-memory or pty links to it."""

from __future__ import annotations

import asyncio
import threading
import time
from collections.abc import Awaitable, Callable, Coroutine
from dataclasses import dataclass
from typing import Any, TypeVar

from melfa.link import Link, LinkSettings, MemoryLink, PacedLink
from melfa.service import Actor, RobotService, Role, ServiceConfig
from melfa.sim import VirtualController, open_sim_link

T = TypeVar("T")

ANN = Actor("ann", Role.STUDENT, "s-ann")
BOB = Actor("bob", Role.STUDENT, "s-bob")
OLGA = Actor("olga", Role.OBSERVER, "s-olga")
IRIS = Actor("iris", Role.INSTRUCTOR, "s-iris")

LINK = LinkSettings(timeout=3.0)


@dataclass(frozen=True)
class Seen:
    """One request as the controller received it: its time, our wall clock, its text."""

    now: float
    wall: float
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
            self.seen.append(Seen(now, time.monotonic(), text.strip("\r")))
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

    def __init__(self, controller: VirtualController, *, pace: bool = False) -> None:
        self.controller = controller
        self.pace = pace
        self.opened: list[Link] = []
        self.memory: list[MemoryLink] = []

    def __call__(self) -> Link:
        link: Link = open_sim_link(LINK, controller=self.controller)
        assert isinstance(link, MemoryLink)
        self.memory.append(link)
        if self.pace:
            link = PacedLink(link)
        self.opened.append(link)
        return link


def make_service(
    controller: VirtualController, *, pace: bool = False, **config: Any
) -> tuple[RobotService, Links]:
    links = Links(controller, pace=pace)
    return RobotService(links, config=ServiceConfig(**config)), links


def run(coro: Coroutine[Any, Any, T], timeout: float = 60.0) -> T:
    """Run a test coroutine; the timeout only guards against hangs."""

    async def guarded() -> T:
        return await asyncio.wait_for(coro, timeout)

    return asyncio.run(guarded())


async def until(predicate: Callable[[], bool], timeout: float = 10.0) -> bool:
    """Wait (generously) until ``predicate`` holds; False on timeout."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        await asyncio.sleep(0.01)
    return predicate()


async def gather_all(*aws: Awaitable[Any]) -> list[Any]:
    return list(await asyncio.gather(*aws, return_exceptions=True))
