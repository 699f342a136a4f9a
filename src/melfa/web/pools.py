"""Thread pools with one job each, so nothing slow stands in front of something urgent.

A login flood runs Argon2 in ``hash``; a student's big `/api/check` runs in ``cpu`` (worker
processes), the planning of a *Load project* in ``load`` (its own worker process); store
reads and writes (session lookups) in ``db``; the session lookup of a STOP in ``stop``,
which nothing else uses. Each pool admits at most ``workers + queue`` calls at a time and
refuses the rest at once with `Busy` (503 and a Retry-After), so a flood never builds an
unbounded queue or memory. Nothing here touches asyncio's default executor.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import functools
import importlib
import multiprocessing
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import ParamSpec, TypeVar

P = ParamSpec("P")
T = TypeVar("T")


PARENT_CHECK_S = 0.5
"""How often a worker process looks whether the server that started it still lives."""


WORKER_NICENESS = 10
"""How much lower a worker process's CPU priority is than the server's: on a machine short
of CPU (two cores, a class typing), the server's event loop and STOP go before checks and
load plans, which can wait a few milliseconds more."""


def start_worker(parent: int) -> None:
    """A worker process's first step: ignore SIGINT (the server decides), step back in the
    CPU queue (`WORKER_NICENESS`), follow ``parent``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with contextlib.suppress(OSError):
        os.nice(WORKER_NICENESS)
    follow_parent(parent)


def follow_parent(parent: int) -> None:
    """In a worker process: exit as soon as ``parent`` (the server) is gone, even when it
    was killed with SIGKILL and could not shut its pool down (the worker would otherwise
    wait on its queue for ever)."""

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_CHECK_S)
        os._exit(0)

    threading.Thread(target=watch, name="melfa-follow-parent", daemon=True).start()


class Busy(Exception):
    """A pool is full: the caller should try again shortly."""

    def __init__(self, pool: str) -> None:
        super().__init__(f"the server is busy ({pool}); try again in a moment")
        self.pool = pool


@contextlib.contextmanager
def _sigint_ignored() -> Iterator[None]:
    """SIGINT ignored meanwhile (processes started now inherit that), on the main thread."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class BoundedPool:
    """A thread pool that admits a bounded number of calls (counted on the event loop)."""

    def __init__(self, name: str, workers: int, queue: int, *, processes: bool = False) -> None:
        if workers < 1 or queue < 0:
            raise ValueError(f"pool {name}: workers ≥ 1 and queue ≥ 0")
        self.name = name
        self.limit = workers + queue
        self.pending = 0
        self.refused = 0
        self.done = 0
        self._executor: concurrent.futures.Executor
        if processes:
            # Pure-Python work (checking) in threads would hold the GIL against the event
            # loop; in processes it cannot slow the loop, and its memory is not ours.
            # Ctrl-C on a terminal reaches the whole process group, but the server, not its
            # workers, decides what it means (it shuts them down): workers ignore SIGINT from
            # their first instruction (an ignored signal stays ignored across exec, and
            # Python keeps it so) and again once started: no tracebacks from them.
            context = multiprocessing.get_context("spawn")
            self._executor = concurrent.futures.ProcessPoolExecutor(
                workers,
                mp_context=context,
                initializer=start_worker,
                initargs=(os.getpid(),),
            )
            with _sigint_ignored():
                for _ in range(workers):  # start and warm them now, not on a first check
                    self._executor.submit(importlib.import_module, "melfa.web.routes.check")
        else:
            self._executor = concurrent.futures.ThreadPoolExecutor(workers, f"melfa-{name}")

    async def run(self, fn: Callable[P, T], *args: P.args, **kwargs: P.kwargs) -> T:
        if self.pending >= self.limit:
            self.refused += 1
            raise Busy(self.name)
        self.pending += 1
        try:
            loop = asyncio.get_running_loop()
            return await loop.run_in_executor(
                self._executor, functools.partial(fn, *args, **kwargs)
            )
        finally:
            self.pending -= 1
            self.done += 1

    def end_workers(self) -> None:
        """End the worker processes at once (SIGTERM), whatever they are doing: they keep
        nothing (a check, a load plan), and left to exit on their own, their niced
        interpreters' teardown took seconds of a busy machine's Ctrl-C. Python 3.11 offers
        no public way (3.14's `terminate_workers` is one), so the executor's own list of
        its processes is read, and a pool of threads, or one already shut down, has none."""
        processes = getattr(self._executor, "_processes", None) or {}
        for worker in list(processes.values()):
            worker.terminate()

    def shutdown(self) -> None:
        """Nothing waiting starts; worker processes are ended (`end_workers`), and the
        pool's manager thread is waited for: it closes the pipe that wakes it, and Python's
        exit handler (`concurrent.futures.process._python_exit`) writes to that pipe without
        the lock its closing takes. Left running, the manager sometimes closed the pipe in
        the middle of that write and the server's clean stop ended in "Exception ignored
        … OSError: [Errno 9] Bad file descriptor". Waited for here, it is closed first
        (and soon: its workers are gone, so there is nothing left to wait for). Threads
        are not waited for (the interpreter's exit joins them; they have no such pipe).
        Later Pythons give the pipe a lock of its own (CPython gh-125451); 3.11 has not."""
        self.end_workers()
        processes = isinstance(self._executor, concurrent.futures.ProcessPoolExecutor)
        self._executor.shutdown(wait=processes, cancel_futures=True)


@dataclass(frozen=True)
class PoolSizes:
    """Threads and waiting room of each pool (`WebSettings.pools`)."""

    db_workers: int = 4
    db_queue: int = 256
    hash_workers: int = 2
    """Argon2 in parallel (each uses 64 MiB and one core for ~50 ms)."""
    hash_queue: int = 16
    """Logins waiting for a hash beyond this are refused (503), not queued."""
    cpu_workers: int = 2
    cpu_queue: int = 8
    """`/api/check`, numbering, stripping waiting beyond this are refused (503)."""
    load_workers: int = 1
    load_queue: int = 64
    """Loads (planning an upload) waiting beyond this are refused (503): their own pool,
    so a student's *Load project* never waits behind, or is refused for, the live checks
    of everyone typing."""
    cpu_processes: bool = False
    """Run them in worker processes, started with the server (threads hold the GIL against
    the event loop: a STOP waits). `melfa serve` turns this on; in-process test apps keep
    threads, which start instantly."""


class Pools:
    """The web server's pools."""

    def __init__(self, sizes: PoolSizes | None = None) -> None:
        s = sizes or PoolSizes()
        self.db = BoundedPool("db", s.db_workers, s.db_queue)
        self.hash = BoundedPool("hash", s.hash_workers, s.hash_queue)
        self.cpu = BoundedPool("cpu", s.cpu_workers, s.cpu_queue, processes=s.cpu_processes)
        self.load = BoundedPool("load", s.load_workers, s.load_queue, processes=s.cpu_processes)
        self.stop = BoundedPool("stop", 1, 64)
        """Only the session lookup of a STOP."""

    def shutdown(self) -> None:
        """Every pool shut down; the worker processes of all of them are ended first, so
        they die side by side rather than one pool's after the other's."""
        pools = (self.db, self.hash, self.cpu, self.load, self.stop)
        for pool in pools:
            pool.end_workers()
        for pool in pools:
            pool.shutdown()


__all__ = ["BoundedPool", "Busy", "PoolSizes", "Pools", "follow_parent", "start_worker"]
