"""The CRDT state of each workspace's live document (`web.coedit`), kept beside its
revisions: a workspace's text is its newest revision; this is how the partners' editors
got there, so that edits made offline merge into the same document after a restart."""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass

__all__ = ["LiveDoc", "keep_live_doc", "read_live_doc"]


@dataclass(frozen=True, slots=True)
class LiveDoc:
    """A live document as last saved: its state (one CRDT update holding everything), the
    revision its text was saved as, and the epoch named when the document was made."""

    workspace_id: int
    epoch: str
    revision: int
    state: bytes


def read_live_doc(conn: sqlite3.Connection, workspace_id: int) -> LiveDoc | None:
    row = conn.execute(
        "SELECT epoch, revision, state FROM live_docs WHERE workspace_id = ?", (workspace_id,)
    ).fetchone()
    if row is None:
        return None
    return LiveDoc(workspace_id, row["epoch"], row["revision"], bytes(row["state"]))


def keep_live_doc(conn: sqlite3.Connection, doc: LiveDoc, updated: str) -> None:
    conn.execute(
        "INSERT INTO live_docs (workspace_id, epoch, revision, state, updated)"
        " VALUES (?, ?, ?, ?, ?) ON CONFLICT (workspace_id) DO UPDATE SET"
        " epoch = excluded.epoch, revision = excluded.revision, state = excluded.state,"
        " updated = excluded.updated",
        (doc.workspace_id, doc.epoch, doc.revision, doc.state, updated),
    )
