"""The queues of the shared robots: one JSON document per target, written whole at each
transition of its queue (`melfa.service.queue.TurnQueue.to_doc`), read back at start."""

from __future__ import annotations

import json
from concurrent.futures import Future
from typing import Any

from melfa.store.db import Database
from melfa.store.timeutil import to_text

__all__ = ["QueueDocs"]


class QueueDocs:
    """Load and save the queue of a target (``lab``)."""

    def __init__(self, db: Database) -> None:
        self.db = db

    def load(self, target: str) -> dict[str, Any] | None:
        row = self.db.read(
            lambda c: c.execute("SELECT doc FROM queues WHERE target = ?", (target,)).fetchone()
        )
        if row is None:
            return None
        doc: dict[str, Any] = json.loads(row["doc"])
        return doc

    def save(self, target: str, doc: dict[str, Any]) -> Future[None]:
        """Queue the write on the store's writer and return at once (the event loop never
        waits on the disk); writes keep their order."""
        text = json.dumps(doc, sort_keys=True)
        at = to_text(self.db.clock())

        def write(conn: Any) -> None:
            conn.execute(
                "INSERT INTO queues (target, doc, updated) VALUES (?, ?, ?)"
                " ON CONFLICT (target) DO UPDATE SET doc = excluded.doc,"
                " updated = excluded.updated",
                (target, text, at),
            )

        return self.db.submit_write(write)
