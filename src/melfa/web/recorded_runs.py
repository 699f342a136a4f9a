"""Where the lab robot's recorded runs go: `RunKeeper` is the service's sink
(`melfa.service.recording`). When a recording ends it finds the simulated run to compare
with (the runner's passed pre-flight of the same fingerprint, else a partner's), works out
the report (`melfa.service.recording_compare`), encodes the frames and stores the run, off
the event loop. The passed pre-flights it compares with are the store's one record of them
(`melfa.store.preflights`, kept by `melfa.web.preflight_passes`)."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any, TypeVar

from melfa.service.recording import Recording
from melfa.service.recording_compare import (
    Comparison,
    SimulatedRun,
    compare,
    unpack,
)
from melfa.service.recording_frames import encode
from melfa.store.runs import NewRun
from melfa.web.context import WebContext
from melfa.web.pools import Busy

_log = logging.getLogger("melfa.web.runs")
T = TypeVar("T")
RETRY_MAX_S = 5.0
"""Longest pause between two tries of a full pool: a class checking as it types fills the
CPU pool for moments, and a run's record must not be lost to that."""


async def patiently(
    call: Callable[[], Awaitable[T]],
    sleep: Callable[[float], Awaitable[None]] = asyncio.sleep,
) -> T:
    """``call()`` again, after a growing pause, for as long as its pool is full."""
    pause = 0.1
    while True:
        try:
            return await call()
        except Busy:
            await sleep(pause)
            pause = min(RETRY_MAX_S, pause * 2)


def report_of(comparison: Comparison) -> dict[str, Any]:
    """The stored report (what the run routes send as ``report``)."""
    largest = comparison.largest
    return {
        "deviation": None
        if largest is None
        else {
            "mm": round(largest.mm, 2),
            "t": largest.t,
            "line": largest.line,
            "real": [round(v, 2) for v in largest.real],
            "simulated": [round(v, 2) for v in largest.simulated],
        },
        "compared": comparison.compared,
        "cycle_difference": None
        if comparison.cycle_difference is None
        else round(comparison.cycle_difference, 3),
    }


class RunKeeper:
    """Stores the lab robot's recordings (the service's sink, event loop only)."""

    def __init__(self, context: WebContext, target: str) -> None:
        self.context = context
        self.target = target
        self._pending: set[asyncio.Task[None]] = set()
        self.saved = 0
        """Runs stored since the server started (tests wait on it)."""

    def __call__(self, recording: Recording) -> None:
        task = asyncio.get_running_loop().create_task(self._save(recording))
        self._pending.add(task)
        task.add_done_callback(self._pending.discard)

    async def drain(self) -> None:
        """Wait for the runs being stored (before the store closes)."""
        while self._pending:
            await asyncio.gather(*list(self._pending), return_exceptions=True)

    async def _save(self, rec: Recording) -> None:
        context = self.context
        store = context.store
        try:
            simulation = None
            fingerprint = rec.fingerprint
            if fingerprint is not None:
                cell = context.preflight.version  # the cell the arm ran in
                simulation = await patiently(
                    lambda: context.db(
                        store.preflights.simulation, rec.user, fingerprint, cell=cell
                    )
                )
            simulated: SimulatedRun | None = (
                unpack(simulation.path) if simulation is not None else None
            )
            comparison = await patiently(
                lambda: context.cpu(compare, rec.frames, simulated, rec.cycle_time)
            )
            frames = await patiently(lambda: context.cpu(encode, rec.frames))
            loaded = rec.loaded
            run = NewRun(
                target=self.target,
                username=rec.user,
                started=rec.started_at,
                duration=rec.duration,
                outcome=(rec.outcome.value if rec.outcome else "unknown"),
                fingerprint=rec.fingerprint,
                loaded_by=loaded.user if loaded else None,
                program=loaded.program if loaded else None,
                frame_count=len(rec.frames),
                frames=frames,
                simulated=simulation.path if simulation is not None else None,
                simulated_by=simulation.username if simulation is not None else None,
                cycle_real=rec.cycle_time,
                cycle_simulated=comparison.cycle_simulated,
                report=report_of(comparison),
            )
            await patiently(lambda: context.db(store.runs.save, run))
            self.saved += 1
        except Exception:
            _log.exception("the run of %s could not be stored", rec.user)


__all__ = ["RunKeeper", "patiently", "report_of"]
