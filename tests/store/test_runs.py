"""Recorded runs in a real SQLite file: saved, listed per user or for everyone, read back
with their blobs, thinned as they age (the summary stays). The simulated path a run is
compared with is a passed pre-flight's: tests/store/test_preflights.py."""

from __future__ import annotations

from pathlib import Path

import pytest

from melfa.store import Store
from melfa.store.errors import NotFound
from melfa.store.runs import NewRun
from melfa.store.thinning import Retention
from tests.store.conftest import CHEAP, FakeClock


def _run(store: Store, clock: FakeClock, user: str = "ann", **fields: object) -> int:
    values: dict[str, object] = {
        "target": "lab",
        "username": user,
        "started": clock(),
        "duration": 12.5,
        "outcome": "finished",
        "fingerprint": "f" * 64,
        "loaded_by": user,
        "program": "MOV P1\nEND\n",
        "frame_count": 3,
        "frames": b"\x01frames",
        "cycle_real": 12.5,
        "report": {"deviation_mm": 3.5},
    }
    values.update(fields)
    return store.runs.save(NewRun(**values))  # type: ignore[arg-type]


def test_a_run_is_saved_and_read_back(store: Store, clock: FakeClock) -> None:
    run_id = _run(store, clock, simulated=b"path", simulated_by="bob", cycle_simulated=10.0)
    run = store.runs.get(run_id)
    assert run.frames == b"\x01frames" and run.simulated == b"path"
    assert run.program == "MOV P1\nEND\n"
    info = run.info
    assert (info.username, info.target, info.outcome, info.started) == (
        "ann",
        "lab",
        "finished",
        clock(),
    )
    assert info.frames_bytes == len(b"\x01frames") and not info.thinned
    assert info.report == {"deviation_mm": 3.5}
    assert (info.cycle_real, info.cycle_simulated, info.simulated_by) == (12.5, 10.0, "bob")
    with pytest.raises(NotFound):
        store.runs.get(run_id + 1)


def test_lists_are_newest_first_per_user_or_for_everyone(store: Store, clock: FakeClock) -> None:
    a1 = _run(store, clock, "ann")
    b1 = _run(store, clock, "bob")
    a2 = _run(store, clock, "ann")
    assert [r.id for r in store.runs.list("ann")] == [a2, a1]
    assert [r.id for r in store.runs.list()] == [a2, b1, a1]
    assert [r.id for r in store.runs.list(before=a2, limit=1)] == [b1]


def test_old_runs_lose_their_samples_but_keep_their_summary(
    db_path: Path, clock: FakeClock
) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP, run_retention=Retention(keep_recent=2)) as store:
        ids = []
        for _ in range(4):  # four runs in one hour
            ids.append(_run(store, clock))
            if len(ids) == 1:
                store.runs.keep(ids[0])  # an instructor keeps the first
            clock.advance(minutes=5)
        kept = _run(store, clock, "bob")  # another user's runs are theirs to thin
        clock.advance(minutes=1)
        ids.append(_run(store, clock))
        thinned = {r.id: r.thinned for r in store.runs.list("ann")}
        # Newest two whole; of the older three (one hour), the newest keeps its samples,
        # and ids[0] was kept by hand.
        assert thinned == {ids[4]: False, ids[3]: False, ids[2]: False, ids[1]: True, ids[0]: False}
        gone = store.runs.get(ids[1])
        assert gone.frames is None and gone.simulated is None
        assert gone.info.report == {"deviation_mm": 3.5} and gone.info.outcome == "finished"
        assert not store.runs.get(kept).info.thinned
