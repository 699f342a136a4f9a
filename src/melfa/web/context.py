"""What every request can reach: the store, the lab's robot service, the targets (lab robot
and private simulators), the settings and the registry of open WebSockets
(`app.state.web`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ParamSpec, TypeVar

from melfa.ros.rosapi import ParamBudget
from melfa.service import Actor, RobotService
from melfa.service.queue_keeper import QueueKeeper
from melfa.store import Store
from melfa.web.coedit import CoeditHub
from melfa.web.config import WebSettings
from melfa.web.desk_settings import DeskSettings
from melfa.web.guard import SocketGuard
from melfa.web.pools import Pools
from melfa.web.preflight import Preflight
from melfa.web.staff_edits import StaffEdits
from melfa.web.targets import Targets

P = ParamSpec("P")
T = TypeVar("T")


@dataclass
class Sockets:
    """Open WebSockets per actor (user + web session): the lease ends with the last one."""

    counts: dict[tuple[str, str], int] = field(default_factory=dict)

    def add(self, actor: Actor) -> None:
        key = (actor.user, actor.session_id)
        self.counts[key] = self.counts.get(key, 0) + 1

    def remove(self, actor: Actor) -> int:
        """Forget one socket of ``actor``; how many it still has open."""
        key = (actor.user, actor.session_id)
        left = self.counts.get(key, 1) - 1
        if left <= 0:
            self.counts.pop(key, None)
            return 0
        self.counts[key] = left
        return left

    @property
    def total(self) -> int:
        return sum(self.counts.values())


@dataclass
class WebContext:
    settings: WebSettings
    store: Store
    service: RobotService
    targets: Targets
    """The lab robot (``service``) and every user's private simulator."""
    preflight: Preflight
    """The lab's cell model (the instructor's gate is the lab service's policy)."""
    sockets: Sockets = field(default_factory=Sockets)
    pools: Pools = field(default_factory=Pools)
    guard: SocketGuard = field(default_factory=SocketGuard)
    rosapi_params: ParamBudget = field(default_factory=ParamBudget)
    """The rosapi parameters every /rosbridge socket holds, against one total."""
    queues: dict[str, QueueKeeper] = field(default_factory=dict)
    """The queue of each shared robot, by target id (``lab``)."""
    staff_edits: StaffEdits = field(default_factory=StaffEdits)
    """Which staff sign-ins chose to edit which of others' workspaces (else read-only)."""
    coedit: CoeditHub = field(init=False)
    """Live co-editing: the open workspaces' shared documents (set by `create_app`)."""
    desk: DeskSettings = field(init=False)
    """The lab robot's desk settings, saved across restarts (set by `create_app`)."""

    async def db(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        """Run a store call off the event loop, in the store's own pool (never behind a
        password hash or a check)."""
        return await self.pools.db.run(fn, *args, **kwargs)

    async def hash(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        """Run something that hashes a password (Argon2) in the bounded hash pool."""
        return await self.pools.hash.run(fn, *args, **kwargs)

    async def cpu(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        """Run checking, numbering or stripping in the bounded CPU pool."""
        return await self.pools.cpu.run(fn, *args, **kwargs)

    async def load(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        """Plan an upload in the loads' own pool (never behind the live checks)."""
        return await self.pools.load.run(fn, *args, **kwargs)


__all__ = ["Sockets", "WebContext"]
