"""What passed pre-flight, in a real SQLite file: the one record the instructor's gate reads
at start (`Preflights.passes`) and a real run is compared with (`Preflights.simulation`: the
runner's own pass first, else a partner's, in the cell the run ran in first); a pass in an
earlier version of the cell is kept beside the new one; rows kept before migration
0017_preflights survive it for the comparison, without digests the gate could count."""

from __future__ import annotations

import sqlite3
from pathlib import Path

from melfa.store import MIGRATIONS, Database, Store
from melfa.store.preflights import NewPass, Pass
from tests.store.conftest import CHEAP, FakeClock


def _pass(
    store: Store,
    user: str,
    fp: str,
    cycle: float | None,
    path: bytes,
    cell: str = "",
    program: str = "p",
    points: str = "q",
) -> None:
    store.preflights.record(NewPass(user, fp, program, points, cell, cycle, path))


def test_a_run_is_compared_with_the_runners_own_simulation_else_a_partners(
    store: Store, clock: FakeClock
) -> None:
    fp = "a" * 64
    assert store.preflights.simulation("ann", fp) is None
    _pass(store, "bob", fp, 9.0, b"bob's")
    found = store.preflights.simulation("ann", fp)
    assert found is not None and (found.username, found.path) == ("bob", b"bob's")
    clock.advance(minutes=1)
    _pass(store, "ann", fp, 9.5, b"ann's")
    clock.advance(minutes=1)
    _pass(store, "bob", fp, 9.1, b"bob's again")  # newer, but not hers
    found = store.preflights.simulation("ANN", fp)
    assert found is not None and (found.username, found.cycle_time, found.path) == (
        "ann",
        9.5,
        b"ann's",
    )
    _pass(store, "ann", fp, 8.0, b"ann's again")  # replaces her older one (same cell)
    found = store.preflights.simulation("ann", fp)
    assert found is not None and found.path == b"ann's again"
    assert store.preflights.simulation("ann", "b" * 64) is None


def test_a_run_is_compared_with_a_simulation_in_the_cell_it_ran_in_first(
    store: Store, clock: FakeClock
) -> None:
    """Hers from before the instructor's edit of the cell loses to a partner's after it;
    with none in that cell, one from an earlier cell (hers first) is still the one."""
    fp = "c" * 64
    _pass(store, "ann", fp, 9.0, b"ann's, old cell", cell="old")
    clock.advance(minutes=1)
    _pass(store, "bob", fp, 9.4, b"bob's, new cell", cell="new")
    clock.advance(minutes=1)
    _pass(store, "cyd", fp, 9.2, b"cyd's, old cell", cell="old")
    found = store.preflights.simulation("ann", fp, cell="new")
    assert found is not None and found.path == b"bob's, new cell"
    found = store.preflights.simulation("ann", fp, cell="old")
    assert found is not None and found.path == b"ann's, old cell"
    found = store.preflights.simulation("ann", fp, cell="newer still")
    assert found is not None and found.path == b"ann's, old cell"
    _pass(store, "ann", fp, 9.3, b"ann's, new cell", cell="new")  # again
    found = store.preflights.simulation("ann", fp, cell="new")
    assert found is not None and found.path == b"ann's, new cell"
    found = store.preflights.simulation("ann", fp, cell="old")  # her old one is kept
    assert found is not None and found.path == b"ann's, old cell"


def test_the_gate_reads_every_pass_in_every_cell_oldest_first(
    db_path: Path, clock: FakeClock
) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        assert store.preflights.passes() == []
        _pass(store, "ann", "f1", 4.0, b"1", cell="a", program="p1", points="q1")
        clock.advance(minutes=1)
        _pass(store, "bob", "f1", 4.5, b"2", cell="b", program="p1", points="q1")
        clock.advance(minutes=1)
        _pass(store, "ann", "f2", None, b"3", cell="b", program="p2", points="q2")
    with Store(db_path, clock=clock, hasher=CHEAP) as store:  # reopened: all kept
        assert store.preflights.passes() == [
            Pass("p1", "q1", "a", 4.0),
            Pass("p1", "q1", "b", 4.5),
            Pass("p2", "q2", "b", None),
        ]
        clock.advance(minutes=1)
        _pass(store, "ann", "f1", 3.9, b"4", cell="a", program="p1", points="q1")  # again
        assert store.preflights.passes()[-1] == Pass("p1", "q1", "a", 3.9)
        assert len(store.preflights.passes()) == 3


def test_simulations_kept_before_0017_survive_for_the_comparison_only(db_path: Path) -> None:
    """A database at 0016 with a kept simulation: after the migration its path still serves
    the comparison; the gate cannot count it (its digests were never kept)."""
    before = tuple(m for m in MIGRATIONS if m.name < "0017")
    Database(db_path, migrations=before).close()
    conn = sqlite3.connect(db_path)
    with conn:
        conn.execute(
            "INSERT INTO simulations (username, fingerprint, created, cycle_time, path, cell)"
            " VALUES ('ann', 'f', '2025-09-01T08:00:00.000000Z', 7.5, x'0102', 'a')"
        )
    conn.close()
    with Store(db_path, hasher=CHEAP) as store:
        found = store.preflights.simulation("ann", "f", cell="a")
        assert found is not None and (found.cycle_time, found.path) == (7.5, b"\x01\x02")
        assert store.preflights.passes() == []
        tables = store.db.read(
            lambda c: {r[0] for r in c.execute("SELECT name FROM sqlite_master")}
        )
        assert "simulations" not in tables
