"""`PrivateSimulator`: one person's own virtual RV-6S, driven by its own `RobotService`.

The lab's robot is shared and leased; a private simulator belongs to one user, so every
frontend can send it the same typed commands (load, run, jog, move, hand, servo, override)
through the same service code, while a debugger reaches into the controller directly. Both
go through one lock: the service's worker thread talks to the controller over an
in-memory link, the debugger calls it from the event loop, never at the same time.

Time: the controller's clock is this object's `now()` (seconds since it was made), the same
for the link and the debugger, so a step taken by the debugger and a poll by the service
agree on what time it is.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import TypeVar

from melfa.link import Link, LinkSettings
from melfa.service.audit import AuditSink
from melfa.service.config import ServiceConfig
from melfa.service.events import Actor
from melfa.service.service import RobotService
from melfa.sim import SimConfig, VirtualController, open_sim_link

T = TypeVar("T")

PRIVATE_SESSION = "private"
"""The session id every actor of a private simulator has: all of its owner's tabs and
clients are one operator, so its lease never stands between them."""

PRIVATE_SERVICE_CONFIG = ServiceConfig(poll_floor_s=0.05, idle_poll_s=1.0)
"""A private simulator polls at most 20 times a second (the IDE shows 20 states a second):
sixty of them must leave the lab robot's link and the machine's two cores alone."""


class PrivateSimulator:
    """A virtual controller, the lock that guards it, and the service that drives it."""

    def __init__(
        self,
        owner: str,
        *,
        config: ServiceConfig | None = None,
        sim_config: SimConfig | None = None,
        audit: AuditSink | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.owner = owner
        self.controller = VirtualController(sim_config)
        self.lock = threading.Lock()
        self._clock = clock
        self._origin = clock()
        self.service = RobotService(
            self._open_link,
            config=config or PRIVATE_SERVICE_CONFIG,
            audit=audit,
            clock=clock,
            gated=False,  # its own, lighter policy: where the simulation happens
        )

    def now(self) -> float:
        """The controller's time: seconds since this simulator was made."""
        return self._clock() - self._origin

    def _open_link(self) -> Link:
        return open_sim_link(
            LinkSettings(), controller=self.controller, clock=self.now, lock=self.lock
        )

    def actor(self, actor: Actor) -> Actor:
        """``actor`` as this simulator's operator (one per owner, whatever the session)."""
        return Actor(actor.user, actor.role, PRIVATE_SESSION)

    def call(self, fn: Callable[[VirtualController, float], T]) -> T:
        """Run ``fn(controller, now)`` under the lock, after bringing the controller up to
        now (a debugger's pause or step happens at the present moment)."""
        with self.lock:
            now = self.now()
            self.controller.advance(now)
            return fn(self.controller, now)

    async def start(self) -> PrivateSimulator:
        await self.service.start()
        return self

    async def close(self) -> None:
        await self.service.close()


__all__ = ["PRIVATE_SERVICE_CONFIG", "PRIVATE_SESSION", "PrivateSimulator"]
