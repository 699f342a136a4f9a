"""The revision log of a workspace's content: how a save becomes a revision, is merged
with what was saved since its base, and how autosaves are thinned.

Rules (docs/store.md): saving never rewrites a revision; a save on an older revision is
merged line by line (`merge.merge3`: no line dropped), refused with `SaveConflict` only
when that revision is no longer kept; saving the content already there adds nothing;
autosaves are thinned by `AUTOSAVE_RETENTION` (or the store's own `Retention`), every other
reason is kept. The functions take the writer's connection: `melfa.store.workspaces.Workspaces`
calls them inside its transactions.
"""

from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from datetime import datetime

from melfa.store.errors import InvalidValue, NotFound, SaveConflict
from melfa.store.merge import merge3
from melfa.store.models import Revision, RevisionInfo, SaveReason, User
from melfa.store.rows import record
from melfa.store.thinning import Retention, thinned
from melfa.store.timeutil import from_text, to_text

__all__ = [
    "AUTOSAVE_RETENTION",
    "MAX_TEXT_CHARS",
    "SaveResult",
    "add_revision",
    "check_size",
    "head_revision",
    "list_revisions",
    "read_revision",
]

MAX_TEXT_CHARS = 1_000_000
"""Per program or points text: far above any real program, low enough to bound the disk."""


AUTOSAVE_RETENTION = Retention(keep_recent=50)
"""How autosaves are thinned: the newest 50 of a workspace all kept (undo for the last
stretch of typing), then one an hour for a week, then one a day, forever. Explicit saves,
imports and restores are never pruned."""


@dataclass(frozen=True, slots=True)
class SaveResult:
    """The workspace's newest revision after a save, and whether the save added it."""

    revision: Revision
    created: bool


def check_size(field: str, text: str) -> None:
    if len(text) > MAX_TEXT_CHARS:
        raise InvalidValue(field, f"is {len(text)} characters; at most {MAX_TEXT_CHARS} are kept")


def revision_of(row: sqlite3.Row) -> Revision:
    return record(Revision, row, created=from_text, reason=SaveReason)


def head_revision(conn: sqlite3.Connection, workspace_id: int, number: int) -> Revision | None:
    """Revision ``number`` (a workspace's head), None for 0 (never saved) or one not kept."""
    if number == 0:
        return None
    row = conn.execute(
        "SELECT * FROM revisions WHERE workspace_id = ? AND number = ?", (workspace_id, number)
    ).fetchone()
    return None if row is None else revision_of(row)


def _empty(workspace_id: int, created: datetime) -> Revision:
    """The content of a never-saved workspace, as revision 0."""
    return Revision(workspace_id, 0, None, created, SaveReason.SAVE, "", "")


def add_revision(
    conn: sqlite3.Connection,
    retention: Retention,
    workspace_id: int,
    program: str,
    points: str,
    base: int | None,
    author: User | None,
    reason: SaveReason,
    now: datetime,
    restored_from: int | None,
) -> SaveResult:
    """Store new content on top of revision ``base`` (None: on whatever is newest), merged
    with what was saved since; nothing added when the content is already there."""
    ws = conn.execute("SELECT head, created FROM workspaces WHERE id = ?", (workspace_id,))
    row = ws.fetchone()
    if row is None:
        raise NotFound(f"no workspace {workspace_id}")
    head_number: int = row["head"]
    head = head_revision(conn, workspace_id, head_number)
    current = head if head is not None else _empty(workspace_id, from_text(row["created"]))
    if current.program == program and current.points == points:
        return SaveResult(current, created=False)
    if base is not None and base != current.number:
        old = head_revision(conn, workspace_id, base) if 0 < base < current.number else None
        if old is None and base != 0:
            raise SaveConflict(base, current)
        old_program, old_points = (old.program, old.points) if old else ("", "")
        program = merge3(old_program, current.program, program)
        points = merge3(old_points, current.points, points)
        if current.program == program and current.points == points:
            return SaveResult(current, created=False)
    number = head_number + 1
    conn.execute(
        "INSERT INTO revisions (workspace_id, number, author_id, author, created, reason,"
        " program, points, restored_from) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
        (
            workspace_id,
            number,
            None if author is None else author.id,
            None if author is None else author.username,
            to_text(now),
            reason.value,
            program,
            points,
            restored_from,
        ),
    )
    conn.execute("UPDATE workspaces SET head = ? WHERE id = ?", (number, workspace_id))
    if reason is SaveReason.AUTOSAVE:
        _prune(conn, retention, workspace_id, now)
    revision = Revision(
        workspace_id,
        number,
        None if author is None else author.username,
        now,
        reason,
        program,
        points,
        restored_from,
    )
    return SaveResult(revision, created=True)


def _prune(
    conn: sqlite3.Connection, retention: Retention, workspace_id: int, now: datetime
) -> None:
    rows = conn.execute(
        "SELECT id, number, created FROM revisions WHERE workspace_id = ?"
        " AND reason = 'autosave' AND kept = 0 ORDER BY number DESC",
        (workspace_id,),
    ).fetchall()
    # The save just made is the newest row: first in its hour, it always stays.
    older = ((row["id"], from_text(row["created"])) for row in rows[retention.keep_recent :])
    doomed = thinned(older, now, retention.hourly_for)
    conn.executemany("DELETE FROM revisions WHERE id = ?", [(i,) for i in doomed])


def list_revisions(
    conn: sqlite3.Connection, workspace_id: int, limit: int, before: int | None
) -> list[RevisionInfo]:
    """History without the texts, newest first; ``before`` a revision number to page
    further back; 1 to 1,000 at a time."""
    limit = max(1, min(limit, 1000))
    upper = before if before is not None else 2**62
    rows = conn.execute(
        "SELECT workspace_id, number, author, created, reason, restored_from,"
        " length(program) AS pc, length(points) AS qc FROM revisions"
        " WHERE workspace_id = ? AND number < ? ORDER BY number DESC LIMIT ?",
        (workspace_id, upper, limit),
    ).fetchall()
    return [
        RevisionInfo(
            r["workspace_id"],
            r["number"],
            r["author"],
            from_text(r["created"]),
            SaveReason(r["reason"]),
            r["restored_from"],
            r["pc"],
            r["qc"],
        )
        for r in rows
    ]


def read_revision(conn: sqlite3.Connection, workspace_id: int, number: int) -> Revision:
    """One revision with its texts; `NotFound` if it never existed or was thinned."""
    row = conn.execute(
        "SELECT * FROM revisions WHERE workspace_id = ? AND number = ?",
        (workspace_id, number),
    ).fetchone()
    if row is None:
        raise NotFound(f"workspace {workspace_id} has no revision {number}")
    return revision_of(row)
