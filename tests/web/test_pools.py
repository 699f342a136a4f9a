"""The server's pools: worker processes stand behind the server for the CPU."""

from __future__ import annotations

import asyncio
import os

from melfa.web.pools import WORKER_NICENESS, BoundedPool


def test_worker_processes_run_at_a_lower_cpu_priority_than_the_server() -> None:
    """Checks and load plans run in worker processes one step back in the CPU queue
    (niceness + 10), so on two busy cores the server's event loop, and STOP with it, is
    scheduled before them."""
    pool = BoundedPool("cpu", 1, 0, processes=True)
    try:
        theirs = asyncio.run(pool.run(os.nice, 0))  # nice(0) reads the niceness
    finally:
        pool.shutdown()
    ours = os.nice(0)
    assert theirs == min(19, ours + WORKER_NICENESS)
