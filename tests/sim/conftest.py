"""Fixtures for simulator tests (usable by anyone: see tests/fixtures_sim.py for the
repo-wide ones)."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from melfa.sim import NO_PACING, PtyServer, SimConfig, VirtualController
from tests.fixtures_sim import Driver, not_strict, sim_pty_path, sim_tcp_url

__all__ = ["not_strict", "sim_pty_path", "sim_tcp_url"]  # repo-wide fixtures, re-exported here


@pytest.fixture(autouse=True)
def _serve_everything(not_strict: None) -> None:
    """The simulator's own tests cover every command it serves, the documented-only ones
    too; tests of strict mode ask for it explicitly."""


@pytest.fixture
def sim() -> VirtualController:
    """A fresh virtual controller with default options."""
    return VirtualController()


@pytest.fixture
def drive(sim: VirtualController) -> Driver:
    """A request driver on `sim` with a hand-moved clock (starts at 0)."""
    return Driver(sim)


@pytest.fixture
def ready(drive: Driver) -> Driver:
    """OPEN, CNTLON, SRVON done."""
    drive.ok("OPEN=TEST")
    drive.ok("CNTLON")
    drive.ok("SRVON")
    return drive


@pytest.fixture
def no_jog_config() -> SimConfig:
    return SimConfig(jog_supported=False)


@pytest.fixture
def pty_server() -> Iterator[PtyServer]:
    with PtyServer(pacing=NO_PACING) as server:
        yield server
