"""The server's pools: worker processes stand behind the server for the CPU."""

from __future__ import annotations

import asyncio
import contextlib
import os
import signal
import threading
from pathlib import Path

import pytest

from melfa.web.pools import WORKER_NICENESS, BoundedPool
from tests.waiting import wait_until


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


def work_that_never_ends(started: str) -> None:
    """In a worker: a check that never ends. It says it started, then blocks on an event
    that nothing ever sets, so only the pool's shutdown can end it."""
    Path(started).touch()
    threading.Event().wait()


def _gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except FileNotFoundError:
        return True
    return state == "Z"


def test_a_worker_still_at_work_when_the_server_stops_is_ended_not_waited_for(
    tmp_path: Path,
) -> None:
    """Ctrl-C on `melfa serve`: the server's exit joins its worker processes, so one still
    at work (a big check, a load plan) must be ended by `shutdown`, not left to finish:
    it keeps nothing (before, the exit waited for the workers to wind down on their own,
    seconds on a busy machine)."""
    pool = BoundedPool("cpu", 1, 1, processes=True)
    started = tmp_path / "started"

    async def main() -> None:
        worker = await pool.run(os.getpid)
        busy = asyncio.ensure_future(pool.run(work_that_never_ends, str(started)))
        try:
            await asyncio.to_thread(wait_until, started.exists, 120, "the work to start")
            pool.shutdown()
            await asyncio.to_thread(wait_until, lambda: _gone(worker), 60, "the worker to end")
            with contextlib.suppress(Exception):
                await busy  # failed: its worker was ended
        finally:
            with contextlib.suppress(OSError):
                os.kill(worker, signal.SIGKILL)  # not left behind if the test fails

    try:
        asyncio.run(main())
    finally:
        pool.shutdown()


@pytest.mark.parametrize("at_work", [False, True], ids=["idle", "a worker at work"])
def test_a_pool_shut_down_leaves_no_thread_behind_to_race_the_exit(
    tmp_path: Path, at_work: bool
) -> None:
    """`melfa serve`'s clean stop sometimes ended in "Exception ignored in … _python_exit
    … OSError: [Errno 9] Bad file descriptor": a process pool's manager thread closes the
    pipe that wakes it, and Python's exit handler writes to that pipe without the lock the
    closing takes, so a manager still winding down at exit could close it in the middle of
    the write. Once `shutdown` has returned, no thread of the pool may be left running
    (so nothing can close that pipe later): idle, or with a worker at work (its manager
    then sees the worker ended, not done)."""
    before = set(threading.enumerate())
    pool = BoundedPool("cpu", 1, 1, processes=True)
    started = tmp_path / "started"

    async def main() -> asyncio.Future[None] | None:
        await pool.run(os.getpid)
        if not at_work:
            return None
        busy = asyncio.ensure_future(pool.run(work_that_never_ends, str(started)))
        await asyncio.to_thread(wait_until, started.exists, 120, "the work to start")
        return busy

    try:
        asyncio.run(main())  # a task still at work is cancelled here: its worker is not
        pool.shutdown()
        left = [t.name for t in threading.enumerate() if t not in before and t.is_alive()]
    finally:
        pool.shutdown()
    assert left == []
