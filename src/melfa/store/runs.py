"""Recorded runs on a shared robot (the simulated paths they are compared with are the
passed pre-flights', `melfa.store.preflights`).

The store keeps what the web hands it: a run's summary (who, which target, when, how long,
how it ended, the program's fingerprint and text, the cycle times, the report as JSON) and
two opaque blobs, the encoded samples (`melfa.service.recording_frames`) and the simulated
path. Saving a run thins that user's older runs in the same transaction
(`melfa.store.run_retention`): a thinned run keeps its summary and loses its blobs.

Who may see which run is not decided here: the web's run routes ask one function
(`melfa.web.routes.runs.may_see`).
"""

from __future__ import annotations

import json
import sqlite3
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from melfa.store.db import Database
from melfa.store.errors import NotFound
from melfa.store.run_retention import RUN_RETENTION, RunAge, to_thin
from melfa.store.thinning import Retention
from melfa.store.timeutil import from_text, to_text

MAX_PAGE = 200


@dataclass(frozen=True, slots=True)
class NewRun:
    """A finished recording, as the web stores it."""

    target: str
    username: str
    started: datetime
    duration: float
    outcome: str
    fingerprint: str | None
    loaded_by: str | None
    program: str | None
    frame_count: int
    frames: bytes
    simulated: bytes | None = None
    simulated_by: str | None = None
    cycle_real: float | None = None
    cycle_simulated: float | None = None
    report: dict[str, Any] | None = None


@dataclass(frozen=True, slots=True)
class RunInfo:
    """A run's summary (what a list shows)."""

    id: int
    target: str
    username: str
    started: datetime
    duration: float
    outcome: str
    fingerprint: str | None
    frame_count: int
    frames_bytes: int | None
    """Size of the stored samples; None once thinned."""
    simulated_by: str | None
    cycle_real: float | None
    cycle_simulated: float | None
    report: dict[str, Any]
    kept: bool

    @property
    def thinned(self) -> bool:
        return self.frames_bytes is None


@dataclass(frozen=True, slots=True)
class Run:
    """A run with its blobs (what a replay needs)."""

    info: RunInfo
    loaded_by: str | None
    program: str | None
    frames: bytes | None
    simulated: bytes | None


_INFO = """
    SELECT id, target, username, started, duration, outcome, fingerprint, frame_count,
           length(frames) AS frames_bytes, simulated_by, cycle_real, cycle_simulated, report,
           kept
    FROM runs
"""


def _info(row: sqlite3.Row) -> RunInfo:
    return RunInfo(
        row["id"],
        row["target"],
        row["username"],
        from_text(row["started"]),
        row["duration"],
        row["outcome"],
        row["fingerprint"],
        row["frame_count"],
        row["frames_bytes"],
        row["simulated_by"],
        row["cycle_real"],
        row["cycle_simulated"],
        json.loads(row["report"] or "{}"),
        bool(row["kept"]),
    )


class Runs:
    """The ``runs`` table."""

    def __init__(self, db: Database, retention: Retention | None = None) -> None:
        self.db = db
        self.retention = retention or RUN_RETENTION

    # --- runs -----------------------------------------------------------------------------

    def save(self, run: NewRun) -> int:
        """Store ``run``; thin its user's older runs. Returns its id."""

        def write(c: sqlite3.Connection) -> int:
            cur = c.execute(
                "INSERT INTO runs (target, username, started, duration, outcome, fingerprint,"
                " loaded_by, program, frame_count, frames, simulated, simulated_by,"
                " cycle_real, cycle_simulated, report)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    run.target,
                    run.username,
                    to_text(run.started),
                    run.duration,
                    run.outcome,
                    run.fingerprint,
                    run.loaded_by,
                    run.program,
                    run.frame_count,
                    run.frames,
                    run.simulated,
                    run.simulated_by,
                    run.cycle_real,
                    run.cycle_simulated,
                    json.dumps(run.report or {}, sort_keys=True),
                ),
            )
            assert cur.lastrowid is not None
            self._thin(c, run.username)
            return cur.lastrowid

        return self.db.write(write)

    def _thin(self, c: sqlite3.Connection, username: str) -> None:
        rows = c.execute(
            "SELECT id, started, kept FROM runs WHERE username = ? AND frames IS NOT NULL",
            (username,),
        ).fetchall()
        ages = [RunAge(r["id"], from_text(r["started"]), bool(r["kept"])) for r in rows]
        doomed = to_thin(ages, self.db.clock(), self.retention)
        c.executemany(
            "UPDATE runs SET frames = NULL, simulated = NULL WHERE id = ?",
            [(i,) for i in doomed],
        )

    def list(
        self, username: str | None = None, *, before: int | None = None, limit: int = 50
    ) -> list[RunInfo]:
        """Runs newest first: ``username``'s, or everyone's (None)."""
        limit = max(1, min(limit, MAX_PAGE))
        clauses: list[str] = []
        params: list[object] = []
        if username is not None:
            clauses.append("username = ?")
            params.append(username)
        if before is not None:
            clauses.append("id < ?")
            params.append(before)
        where = (" WHERE " + " AND ".join(clauses)) if clauses else ""
        params.append(limit)
        rows = self.db.read(
            lambda c: c.execute(_INFO + where + " ORDER BY id DESC LIMIT ?", params).fetchall()
        )
        return [_info(r) for r in rows]

    def get(self, run_id: int) -> Run:
        """One run with its blobs; `NotFound` if there is none."""

        def read(c: sqlite3.Connection) -> Run | None:
            row = c.execute(_INFO + " WHERE id = ?", (run_id,)).fetchone()
            if row is None:
                return None
            blobs = c.execute(
                "SELECT loaded_by, program, frames, simulated FROM runs WHERE id = ?", (run_id,)
            ).fetchone()
            return Run(
                _info(row),
                blobs["loaded_by"],
                blobs["program"],
                blobs["frames"],
                blobs["simulated"],
            )

        found = self.db.read(read)
        if found is None:
            raise NotFound(f"run {run_id} does not exist")
        return found

    def keep(self, run_id: int, kept: bool = True) -> None:
        """Keep a run's samples whatever thinning comes later (or stop keeping them)."""
        changed = self.db.write(
            lambda c: (
                c.execute("UPDATE runs SET kept = ? WHERE id = ?", (int(kept), run_id)).rowcount
            )
        )
        if not changed:
            raise NotFound(f"run {run_id} does not exist")


__all__ = ["MAX_PAGE", "NewRun", "Run", "RunInfo", "Runs"]
