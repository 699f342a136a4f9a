"""The lab robot's desk settings kept across restarts: the simulation gate and the lab's
networks staff switch on the instructor's desk are saved in the store (`store.robot_settings`)
before they apply, read back when the server starts and set on the service's one policy by
the rule of `melfa.service.live_settings` (the start-up option is a floor a saved choice
may only tighten); and where each setting in force came from, which the desk shows."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from dataclasses import dataclass

from melfa.service.lab_network import NetworkError, parse_networks
from melfa.service.live_settings import (
    Choice,
    Networks,
    Origin,
    gate_at_start,
    gate_switched,
    networks_at_start,
    networks_switched,
)
from melfa.service.policy import Policy
from melfa.store.robot_settings import RobotSettings, SavedSetting

GATE = "require_simulation"
"""The gate's name in the store (its value: true or false)."""
LAB_NETWORKS = "lab_networks"
"""The lab's networks' name in the store (its value: a list of CIDR texts; [] anywhere)."""
_log = logging.getLogger("melfa.web.desk")

Saver = Callable[[str, str, object, str], Awaitable[SavedSetting]]
"""``RobotSettings.save`` run off the event loop (the web's store pool)."""


@dataclass(frozen=True)
class StartOptions:
    """What the server was started with for these settings (``melfa serve``)."""

    require_simulation: bool = False
    lab_networks: Networks = ()

    def written(self, name: str) -> str | None:
        """The option as a technician wrote it (``--lab-network 192.168.10.0/24``), or None
        when the server was started without it."""
        if name == GATE:
            return "--require-simulation" if self.require_simulation else None
        if self.lab_networks:
            return "--lab-network " + ",".join(str(n) for n in self.lab_networks)
        return None


class DeskSettings:
    """The desk's settings of one shared robot (``target``), applied to its ``policy``."""

    def __init__(
        self,
        store: RobotSettings,
        save: Saver,
        policy: Policy,
        target: str,
        options: StartOptions,
    ) -> None:
        self.store = store
        self._save = save
        self.policy = policy
        self.target = target
        self.options = options
        self.gate_origin: Origin
        self.networks_origin: Origin
        self._switching = asyncio.Lock()
        """One switch at a time: what applies is what was saved last."""

    def start(self) -> DeskSettings:
        """Read what staff chose before the restart and set the policy by the rule (before
        the server takes its first request)."""
        saved = self.store.load(self.target)
        gate = saved.get(GATE)
        on, self.gate_origin = gate_at_start(
            self.options.require_simulation,
            None if gate is None else Choice(bool(gate.value), gate.by, gate.at),
        )
        if self.policy.gate is not None:
            self.policy.gate.required = on
        networks, self.networks_origin = networks_at_start(
            self.options.lab_networks, self._networks(saved.get(LAB_NETWORKS))
        )
        if self.policy.lab is not None:
            self.policy.lab.networks = networks
        return self

    def _networks(self, saved: SavedSetting | None) -> Choice[Networks] | None:
        if saved is None:
            return None
        try:
            return Choice(parse_networks(saved.value), saved.by, saved.at)
        except (NetworkError, TypeError, AttributeError):
            _log.warning("the saved lab networks %r are not networks: not used", saved.value)
            return None

    async def set_gate(self, on: bool, by: str) -> None:
        """Save the gate, then switch it for every door (a store that fails leaves it as
        it was: nothing applies unsaved)."""
        async with self._switching:
            saved = await self._save(self.target, GATE, on, by)
            if self.policy.gate is not None:
                self.policy.gate.required = on
            choice = Choice(on, saved.by, saved.at)
            self.gate_origin = gate_switched(self.options.require_simulation, choice)

    async def set_networks(self, networks: Networks, by: str) -> None:
        """Save the lab's networks, then set them (as `set_gate`)."""
        written = [str(n) for n in networks]
        async with self._switching:
            saved = await self._save(self.target, LAB_NETWORKS, written, by)
            if self.policy.lab is not None:
                self.policy.lab.networks = networks
            choice = Choice(networks, saved.by, saved.at)
            self.networks_origin = networks_switched(self.options.lab_networks, choice)


__all__ = ["GATE", "LAB_NETWORKS", "DeskSettings", "StartOptions"]
