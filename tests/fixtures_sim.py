"""Simulator fixtures for every test package (import them in tests/conftest.py).

- `sim_pty_path`: a fresh pseudo-terminal served by a fresh virtual controller; open it with
  pyserial at 9600 8E2 (the real serial code path). A new pty per test, because a pty drops
  parity and reopening one with parity set fails.
- `sim_tcp_url`: `tcp://127.0.0.1:<port>` served by a fresh virtual controller.
- `not_strict`: simulators created in the test also serve commands only the manual documents
  (JOG, DSTATE, HNDSTS…). The suite runs every simulator strict (tests/conftest.py); tests of
  the paths melfa keeps for a controller that turns out to accept such a command (continuous
  JOG: `melfa doctor` probes it) ask for this.
- `Driver`: send request strings to a `VirtualController` with a hand-moved clock.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from melfa.protocol.messages import Ok, Reply, decode_reply
from melfa.sim import NO_PACING, PtyServer, TcpServer, VirtualController
from melfa.sim.config import STRICT_ENV


class Driver:
    """Talk to a controller in tests: `send("STATE")` -> reply bytes at the current time.

    The clock only moves when told (`wait(seconds)`), so tests are exact and instant.
    """

    def __init__(self, controller: VirtualController, now: float = 0.0) -> None:
        self.controller = controller
        self.now = now

    def send(self, command: str, robot: int = 1, slot: int = 1) -> bytes:
        """Send `<robot>;<slot>;<command>` and return the raw reply (CR included)."""
        return self.controller.handle(f"{robot};{slot};{command}\r".encode("latin-1"), self.now)

    def reply(self, command: str, slot: int = 1) -> Reply:
        return decode_reply(self.send(command, slot=slot).rstrip(b"\r"))

    def ok(self, command: str, slot: int = 1) -> str:
        """Send and insist on `QoK`; return the answer text."""
        reply = self.reply(command, slot=slot)
        assert isinstance(reply, Ok), (command, reply)
        assert not reply.alarm, (command, reply)
        return reply.answer

    def wait(self, seconds: float) -> None:
        self.now += seconds


@pytest.fixture
def sim_pty_path() -> Iterator[str]:
    """Slave path of a fresh pty served by a fresh `VirtualController` (no pacing)."""
    with PtyServer(VirtualController(), pacing=NO_PACING) as server:
        yield server.new_port()


@pytest.fixture
def sim_tcp_url() -> Iterator[str]:
    """`tcp://127.0.0.1:<port>` served by a fresh `VirtualController` (no pacing)."""
    with TcpServer(VirtualController(), pacing=NO_PACING) as server:
        yield server.url


@pytest.fixture
def not_strict(monkeypatch: pytest.MonkeyPatch) -> None:
    """Simulators created from now on also serve documented-only commands (see above)."""
    monkeypatch.setenv(STRICT_ENV, "0")
