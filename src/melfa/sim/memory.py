"""The in-process link: `--robot sim` with no port, no pty and no thread.

`open_sim_link()` returns comms's `MemoryLink` whose responder is a `VirtualController`
answering at the real time of a monotonic clock (the controller itself has no clock). The
framing is the same `WireSession` the pty and TCP servers use, so garbage and split input
behave alike everywhere. For 9600-baud timing wrap the link in `melfa.link.PacedLink`.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from melfa.link.memory import MemoryLink
from melfa.link.settings import LinkSettings
from melfa.sim.config import SimConfig
from melfa.sim.controller import VirtualController
from melfa.sim.session import WireSession


def open_sim_link(
    settings: LinkSettings | None = None,
    *,
    controller: VirtualController | None = None,
    config: SimConfig | None = None,
    clock: Callable[[], float] = time.monotonic,
    lock: threading.Lock | None = None,
) -> MemoryLink:
    """A `Link` to a virtual controller in this process.

    `controller` lets a caller keep a handle on the simulator (to inspect the arm, or share
    it with a server); `clock` lets tests drive time by hand; `lock` guards the controller
    against other threads that touch it directly (a debugger).

    >>> from melfa.protocol import Request
    >>> link = open_sim_link()
    >>> link.exchange(Request("FROBNICATE"))
    Refused(error=6010, alarm=False, detail='00000')
    >>> link.close()
    """
    sim = controller if controller is not None else VirtualController(config)
    session = WireSession(sim, lock)
    origin = clock()

    def respond(line: bytes) -> bytes:
        answers = session.receive(line + b"\r", clock() - origin)
        return b"".join(answer.reply for answer in answers)

    def on_close() -> None:
        session.disconnect(clock() - origin)

    return MemoryLink(
        respond, settings, description="virtual controller (in process)", on_close=on_close
    )
