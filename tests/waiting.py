"""Waiting in tests without timing anything: one deadline-bounded wait for a condition, and
uvicorn started in a thread with an event for "ready".

`wait_until` is for conditions that have no event to await (a state read over HTTP, a
server process coming up): it returns as soon as the condition holds, and its deadline is
a guard against a hang, never a measurement, so it is generous.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import TypeVar

import uvicorn

T = TypeVar("T")
POLL_S = 0.02
"""How often `wait_until` looks again: often enough not to slow a test down."""


def wait_until(
    condition: Callable[[], T], timeout: float = 30.0, what: str | Callable[[], str] = ""
) -> T:
    """The first truthy value of ``condition()``; AssertionError naming ``what`` (a text, or
    a function giving one, e.g. the state found) when it has not come after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while True:
        value = condition()
        if value:
            return value
        if time.monotonic() > deadline:
            told = what() if callable(what) else what
            raise AssertionError(f"timed out waiting for {told or 'the condition'}")
        time.sleep(POLL_S)


def start_uvicorn(config: uvicorn.Config) -> tuple[uvicorn.Server, threading.Thread]:
    """uvicorn serving ``config`` in a daemon thread, returned once it accepts connections
    (an event set by its start-up, or by its thread ending when start-up failed)."""
    server = uvicorn.Server(config)
    ready = threading.Event()
    serve = server.startup

    async def startup(sockets: object = None) -> None:
        await serve(sockets=sockets)  # type: ignore[arg-type]
        ready.set()

    server.startup = startup  # type: ignore[method-assign]

    def run() -> None:
        try:
            server.run()
        finally:
            ready.set()

    thread = threading.Thread(target=run, name="uvicorn", daemon=True)
    thread.start()
    assert ready.wait(60), "uvicorn neither started nor failed in 60 s"
    assert server.started and thread.is_alive(), "uvicorn did not start"
    return server, thread
