"""Robot tests run through a real pseudo-terminal opened at 9600 8E2 against the virtual
controller (a fresh pty per connection). With ``pytest tests/robot --robot URL`` (or
``MELFA_TEST_ROBOT=URL``) the same tests run against real hardware; tests that need to look
inside the simulator are skipped then.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest

from melfa.link import LinkSettings, SerialLink, open_link
from melfa.robot import Robot, RobotSettings
from melfa.sim import PtyServer, SimConfig, VirtualController

HARDWARE_ENV = "MELFA_TEST_ROBOT"


@pytest.fixture(scope="session")
def hardware(request: pytest.FixtureRequest) -> str | None:
    spec: str | None = request.config.getoption("--robot", default=None)
    return spec or os.environ.get(HARDWARE_ENV) or None


@pytest.fixture
def sim_config() -> SimConfig:
    return SimConfig()


@pytest.fixture
def controller(hardware: str | None, sim_config: SimConfig) -> VirtualController:
    if hardware:
        pytest.skip("inspects the virtual controller")
    return VirtualController(sim_config)


@pytest.fixture
def pty_server(controller: VirtualController) -> Iterator[PtyServer]:
    with PtyServer(controller) as server:
        yield server


LINK = LinkSettings(timeout=10.0)
"""Generous: a loaded machine must not turn a slow reply into a failure."""


@pytest.fixture
def robot(hardware: str | None, request: pytest.FixtureRequest) -> Iterator[Robot]:
    """A robot on a fresh pty to the simulator (or the hardware given with --robot)."""
    if hardware:
        link = open_link(hardware, LINK)
    else:
        server: PtyServer = request.getfixturevalue("pty_server")
        link = SerialLink(server.new_port(), LINK)
    robot = Robot(link, RobotSettings())
    yield robot
    robot.close()
