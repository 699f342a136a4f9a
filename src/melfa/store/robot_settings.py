"""The live settings staff choose on the instructor's desk for each shared robot (the
simulation gate, the lab's networks): one row per setting, its value as JSON with who
chose it and when, so a server restart keeps them. The store keeps what was chosen; which
setting is in force at start is decided above it (`melfa.service.live_settings`)."""

from __future__ import annotations

import json
import sqlite3
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from melfa.store.db import Database
from melfa.store.timeutil import from_text, to_text

__all__ = ["RobotSettings", "SavedSetting"]


@dataclass(frozen=True)
class SavedSetting:
    value: Any
    """The setting's JSON value (``true``; ``["192.168.10.0/24"]``)."""
    by: str
    at: datetime


def _saved(row: sqlite3.Row) -> SavedSetting:
    return SavedSetting(json.loads(row["value"]), row["by"], from_text(row["updated"]))


class RobotSettings:
    """Load and save the desk's settings of a target (``lab``)."""

    def __init__(self, db: Database) -> None:
        self.db = db

    def load(self, target: str) -> dict[str, SavedSetting]:
        """Every saved setting of ``target`` by name (empty: nothing chosen yet)."""
        rows = self.db.read(
            lambda c: c.execute(
                "SELECT name, value, by, updated FROM robot_settings WHERE target = ?",
                (target,),
            ).fetchall()
        )
        return {
            row["name"]: SavedSetting(
                json.loads(row["value"]), row["by"], from_text(row["updated"])
            )
            for row in rows
        }

    def save(self, target: str, name: str, value: Any, by: str) -> SavedSetting:
        """Save ``name`` = ``value`` chosen by ``by`` now (replacing the last choice); waits
        until it is written, so the caller applies only a saved setting."""
        at = self.db.clock()
        text = json.dumps(value, sort_keys=True)

        def write(conn: sqlite3.Connection) -> None:
            conn.execute(
                "INSERT INTO robot_settings (target, name, value, by, updated)"
                " VALUES (?, ?, ?, ?, ?) ON CONFLICT (target, name) DO UPDATE SET"
                " value = excluded.value, by = excluded.by, updated = excluded.updated",
                (target, name, text, by, to_text(at)),
            )

        self.db.write(write)
        return SavedSetting(value, by, at)
