"""What passed pre-flight: the one record (the ``preflights`` table).

A row is one user's passed pre-flight of one program and points as sent, in one version of
the lab's cell (`Cell.digest`): the gate's digests of the program and of the points, the
upload plan's fingerprint of the pair, its cycle time and its simulated path. Two readers
read the same rows: the instructor's gate (`passes`, loaded when the server starts, so a
restart keeps every pass; `melfa.web.preflight_passes` keeps the gate told of each new one)
and the comparison of a recorded real run with its simulation (`simulation`).

Whose pass counts is the gate's rule (`melfa.service.policy.Gate`: anyone's pass of the
same text in the same cell); the store keeps who passed it, for the comparison and the
record.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from melfa.store.db import Database
from melfa.store.timeutil import from_text, to_text

__all__ = ["NewPass", "Pass", "Preflights", "Simulation"]


@dataclass(frozen=True, slots=True)
class NewPass:
    """A pre-flight that passed, as the web keeps it."""

    username: str
    fingerprint: str
    program_digest: str
    points_digest: str
    cell: str
    """The version of the lab's cell it ran in (`Cell.digest`)."""
    cycle_time: float | None
    path: bytes
    """The simulated path, packed (`melfa.service.recording_compare.pack`)."""


@dataclass(frozen=True, slots=True)
class Pass:
    """What the instructor's gate reads of a pass (`melfa.service.policy.Gate.load`)."""

    program_digest: str
    points_digest: str
    cell: str
    cycle_time: float | None


@dataclass(frozen=True, slots=True)
class Simulation:
    """A passed pre-flight's path for a fingerprint (what a real run is compared with)."""

    username: str
    fingerprint: str
    created: datetime
    cycle_time: float | None
    path: bytes


class Preflights:
    """The ``preflights`` table."""

    def __init__(self, db: Database) -> None:
        self.db = db

    def record(self, new: NewPass) -> None:
        """Keep ``new`` (replacing the same user's pass of the same text in the same cell;
        their passes in other versions of the cell stay)."""
        now = to_text(self.db.clock())
        self.db.write(
            lambda c: c.execute(
                "INSERT INTO preflights (username, fingerprint, program_digest, points_digest,"
                " cell, created, cycle_time, path) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
                " ON CONFLICT (username, fingerprint, cell) DO UPDATE"
                " SET program_digest = excluded.program_digest,"
                " points_digest = excluded.points_digest, created = excluded.created,"
                " cycle_time = excluded.cycle_time, path = excluded.path",
                (
                    new.username,
                    new.fingerprint,
                    new.program_digest,
                    new.points_digest,
                    new.cell,
                    now,
                    new.cycle_time,
                    new.path,
                ),
            )
        )

    def passes(self) -> list[Pass]:
        """Every pass the gate can count, oldest first (rows kept before the gate read the
        store have no digests and are left out)."""
        rows = self.db.read(
            lambda c: c.execute(
                "SELECT program_digest, points_digest, cell, cycle_time FROM preflights"
                " WHERE program_digest IS NOT NULL AND points_digest IS NOT NULL"
                " ORDER BY created, rowid"
            ).fetchall()
        )
        return [
            Pass(r["program_digest"], r["points_digest"], r["cell"], r["cycle_time"]) for r in rows
        ]

    def simulation(self, username: str, fingerprint: str, *, cell: str = "") -> Simulation | None:
        """The simulated run a real run of ``fingerprint`` by ``username`` in version
        ``cell`` of the lab's cell is compared with: a pre-flight passed in that cell (their
        own, else the newest a partner passed), else one from an earlier cell (the same
        order). The cell can change the run (its sensors, conveyors, parts), and the gate
        lets a run go only after a pass in the cell as it is: that pass is the one."""
        row = self.db.read(
            lambda c: c.execute(
                "SELECT * FROM preflights WHERE fingerprint = ? ORDER BY cell = ? DESC,"
                " username = ? COLLATE NOCASE DESC, created DESC LIMIT 1",
                (fingerprint, cell, username),
            ).fetchone()
        )
        if row is None:
            return None
        return Simulation(
            row["username"],
            row["fingerprint"],
            from_text(row["created"]),
            row["cycle_time"],
            row["path"],
        )
