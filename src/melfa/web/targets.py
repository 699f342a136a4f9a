"""Targets: which robot a request drives. Every signed-in user has two: the lab's robot the
server was started with (``lab``, shared, leased) and a private virtual RV-6S of their own
(``mine``, made on first use, freed when idle; their programs stay in the workspace).

A request names its target with the ``target`` query parameter (REST) or the socket URL
(``/api/ws?target=mine``); the lab robot is the default, so older clients keep working.
"""

from __future__ import annotations

import asyncio
import contextlib
import enum
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from melfa.service import Actor, RobotService
from melfa.service.audit import AuditSink
from melfa.service.debugging import DebugSession
from melfa.service.simulator import PrivateSimulator
from melfa.vocab.targets import TARGET_LABELS

_log = logging.getLogger("melfa.web.targets")

LAB = "lab"
MINE = "mine"
PRIVATE_LABEL = TARGET_LABELS[MINE]


class TargetKind(enum.Enum):
    LAB = "lab"
    PRIVATE = "private"


@dataclass
class Target:
    """One robot as a user sees it: the service that drives it and how to name them."""

    id: str
    kind: TargetKind
    label: str
    service: RobotService
    simulator: PrivateSimulator | None = None
    debug: DebugSession | None = None
    """The program under the debugger on this private simulator, if any."""
    sockets: int = 0
    last_used: float = field(default_factory=time.monotonic)

    @property
    def shared(self) -> bool:
        """Shared robots are leased; a private simulator has one operator, its owner."""
        return self.simulator is None

    def actor(self, actor: Actor) -> Actor:
        return actor if self.simulator is None else self.simulator.actor(actor)

    async def stop(self, actor: Actor) -> None:
        """STOP: the robot, and on a private simulator the program under the debugger."""
        debug = self.debug
        if debug is not None and not debug.closed:
            with contextlib.suppress(Exception):
                await debug.call(lambda d: d.pause())
        await self.service.stop(actor)


class UnknownTarget(LookupError):
    """A target id that is neither ``lab`` nor ``mine``."""


class Targets:
    """The lab robot and every user's private simulator. Private ones are made on first
    use and closed by `reap` after ``idle_s`` with no request and no open socket."""

    def __init__(
        self,
        lab: RobotService,
        *,
        lab_label: str = TARGET_LABELS[LAB],
        idle_s: float = 1800.0,
        audit: Callable[[str], AuditSink] | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.lab = Target(LAB, TargetKind.LAB, lab_label, lab)
        self.idle_s = idle_s
        self._audit = audit
        self._clock = clock
        self._private: dict[str, Target] = {}
        self._making: dict[str, asyncio.Lock] = {}

    def private(self, user: str) -> Target | None:
        """``user``'s simulator if it exists now (never makes one)."""
        return self._private.get(user)

    @property
    def private_count(self) -> int:
        return len(self._private)

    async def get(self, user: str, target_id: str) -> Target:
        """The target ``target_id`` of ``user``; their simulator is made on first use."""
        if target_id == LAB:
            return self.lab
        if target_id != MINE:
            raise UnknownTarget(target_id)
        target = self._private.get(user)
        if target is None:
            lock = self._making.setdefault(user, asyncio.Lock())
            async with lock:
                target = self._private.get(user)
                if target is None:
                    audit = self._audit(user) if self._audit is not None else None
                    simulator = PrivateSimulator(user, audit=audit, clock=self._clock)
                    await simulator.start()
                    target = Target(
                        MINE,
                        TargetKind.PRIVATE,
                        PRIVATE_LABEL,
                        simulator.service,
                        simulator=simulator,
                        last_used=self._clock(),
                    )
                    self._private[user] = target
                    _log.info("private simulator made for %s", user)
        target.last_used = self._clock()
        return target

    def touch(self, target: Target) -> None:
        target.last_used = self._clock()

    async def reap(self) -> list[str]:
        """Close the private simulators idle for ``idle_s``; whose they were."""
        now = self._clock()
        idle = [
            user
            for user, t in self._private.items()
            if t.sockets == 0 and now - t.last_used >= self.idle_s
        ]
        for user in idle:
            await _close(self._private.pop(user))
            _log.info("private simulator of %s freed after %.0f s idle", user, self.idle_s)
        return idle

    async def close(self) -> None:
        """Close every private simulator (the lab service belongs to the app)."""
        targets, self._private = list(self._private.values()), {}
        for target in targets:
            await _close(target)


async def _close(target: Target) -> None:
    """A private target's debug session, then its simulator."""
    with contextlib.suppress(Exception):
        if target.debug is not None:
            await target.debug.close()
        if target.simulator is not None:
            await target.simulator.close()


__all__ = ["LAB", "MINE", "PRIVATE_LABEL", "Target", "TargetKind", "Targets", "UnknownTarget"]
