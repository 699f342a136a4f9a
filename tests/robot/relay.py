"""A fault-injecting relay between the client and the virtual controller, on a real pty.

The client opens the relay's pty at 9600 8E2 like a serial port; every request line goes
to a real `VirtualController` (strict, 9-digit refusals unless told otherwise), and its reply
comes back, unless a `Fault` says otherwise: swallow it (never answered), hold it and send it
late (just before the next reply), send an unsolicited reply first, answer with another
request's reply, or hang up. `lines` records what reached the relay, so tests can prove
what the controller did (or never) receive.

    relay = FaultRelay()
    relay.add(Fault.drop("SAVE"))
    robot = Robot(SerialLink(relay.new_port(), LinkSettings(timeout=1)))
"""

from __future__ import annotations

import enum
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

from melfa.sim import VirtualController
from tests.robot.fake import FakeController


class Action(enum.Enum):
    DROP = "drop"  # never answer
    LATE = "late"  # answer just before the next reply
    EXTRA_BEFORE = "extra before"  # an unsolicited reply first, then the real one
    REPLACE = "replace"  # answer with `payload` instead
    HANG_UP = "hang up"  # the cable is pulled when the request arrives (not handled)
    HANG_UP_AFTER = "hang up after"  # handled by the controller, then the cable is pulled


@dataclass
class Fault:
    """Apply ``action`` to the ``nth`` (1-based) request whose command contains ``match``."""

    match: str
    action: Action
    nth: int = 1
    payload: bytes = b""
    seen: int = 0
    fired: bool = False

    @classmethod
    def drop(cls, match: str, nth: int = 1) -> Fault:
        return cls(match, Action.DROP, nth)

    @classmethod
    def late(cls, match: str, nth: int = 1) -> Fault:
        return cls(match, Action.LATE, nth)

    @classmethod
    def extra_before(cls, match: str, payload: bytes = b"QoK\r", nth: int = 1) -> Fault:
        return cls(match, Action.EXTRA_BEFORE, nth, payload)

    @classmethod
    def replace(cls, match: str, payload: bytes, nth: int = 1) -> Fault:
        return cls(match, Action.REPLACE, nth, payload)

    @classmethod
    def hang_up(cls, match: str, nth: int = 1, *, after: bool = False) -> Fault:
        return cls(match, Action.HANG_UP_AFTER if after else Action.HANG_UP, nth)


class FaultRelay:
    """A pty served by a `VirtualController`, with faults injected on the way back."""

    def __init__(self, controller: VirtualController | None = None) -> None:
        self.controller = controller or VirtualController()
        self.faults: list[Fault] = []
        self.lines: list[str] = []
        self._held: list[bytes] = []
        self._lock = threading.Lock()
        self._start = time.monotonic()
        self._fakes: list[FakeController] = []

    def new_port(self) -> str:
        """A fresh pty to the same controller and faults (a pty cannot be reopened with
        parity set, so each connection gets its own, as with the real cable replugged)."""
        fake = FakeController(self._answer)
        self._fakes.append(fake)
        return fake.path

    def add(self, *faults: Fault) -> FaultRelay:
        with self._lock:
            self.faults.extend(faults)
        return self

    def commands(self) -> list[str]:
        """Command words received, without the ``robot;slot;`` prefix."""
        return [line.split(";", 2)[-1] for line in self.lines]

    def _answer(self, line: bytes) -> bytes | None:
        text = line.decode("latin-1")
        with self._lock:
            fault = self._fault_for(text)
            if fault is not None and fault.action is Action.HANG_UP:
                return None
            self.lines.append(text)
            reply = self.controller.handle(line + b"\r", time.monotonic() - self._start)
            held, self._held = b"".join(self._held), []
            if fault is None:
                return held + reply
            if fault.action is Action.DROP:
                return held
            if fault.action is Action.LATE:
                self._held.append(reply)
                return held
            if fault.action is Action.EXTRA_BEFORE:
                return held + fault.payload + reply
            if fault.action is Action.REPLACE:
                return held + fault.payload
            assert fault.action is Action.HANG_UP_AFTER
            return None

    def _fault_for(self, text: str) -> Fault | None:
        for fault in self.faults:
            if fault.fired or fault.match not in text:
                continue
            fault.seen += 1
            if fault.seen == fault.nth:
                fault.fired = True
                return fault
        return None

    def close(self) -> None:
        for fake in self._fakes:
            fake.close()


def count_requests(run: Callable[[FaultRelay], object]) -> int:
    """How many requests ``run`` sends through a fault-free relay."""
    relay = FaultRelay()
    try:
        run(relay)
        return len(relay.lines)
    finally:
        relay.close()
