"""Workspaces: each user's or group's program and points, with every save kept.

Thesis chapter 8 asked for stored programs per group and autosave, so that "changes are
not lost if the web page is refreshed". This module says which workspaces there are and who
opens them; their content is a log of revisions written by `melfa.store.revisions`.
Rules (docs/store.md):

* A workspace's content is its newest revision. Saving never rewrites a revision; restoring
  an old one adds a new revision with the old content.
* Saves carry the revision the client edited (`base`). If another save landed in between
  (a partner, the desktop client, a tab that was offline), the two edits are merged line
  by line (`merge.merge3`: no line of either is dropped; where both changed the same
  lines, the ones saved first come first). Only when the base revision is no longer kept
  (thinned) is the save refused with `SaveConflict` carrying the current revision.
* A shared workspace's live document (`web.coedit`) saves with `save_live`: its revision
  and the document's CRDT state together (`live_docs`).
* Saving the content that is already there adds nothing (and never conflicts).
* Explicit saves, imports, restores and the text a restore replaced are kept forever;
  autosaves are thinned
  (`AUTOSAVE_RETENTION`): the newest ones all kept, older ones one per hour, then one per day.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Sequence
from dataclasses import replace

from melfa.store.accounts import Accounts
from melfa.store.db import Database
from melfa.store.errors import AccessDenied, AlreadyExists, InvalidValue, NotFound
from melfa.store.live_docs import LiveDoc, keep_live_doc, read_live_doc
from melfa.store.models import (
    Revision,
    RevisionInfo,
    SaveReason,
    User,
    Workspace,
    WorkspaceKind,
    WorkspaceState,
)
from melfa.store.revisions import (
    AUTOSAVE_RETENTION,
    MAX_TEXT_CHARS,
    SaveResult,
    add_revision,
    check_size,
    head_revision,
    list_revisions,
    read_revision,
)
from melfa.store.thinning import Retention
from melfa.store.timeutil import from_text, to_text
from melfa.store.transfer import (
    ExportedFile,
    FileKind,
    file_kind,
    points_from_file,
    points_to_file,
    program_from_file,
    program_to_file,
)
from melfa.store.workspace_names import DEFAULT_PERSONAL_NAME, clean_name

__all__ = ["MAX_TEXT_CHARS", "SaveResult", "Workspaces"]

_WS_SELECT = """
    SELECT w.id, w.user_id, w.group_id, w.created, w.head, w.name, w.archived, u.username,
           g.name AS group_name
    FROM workspaces AS w
    LEFT JOIN users AS u ON u.id = w.user_id
    LEFT JOIN groups AS g ON g.id = w.group_id
"""


def _workspace(row: sqlite3.Row) -> Workspace:
    personal = row["user_id"] is not None
    return Workspace(
        row["id"],
        WorkspaceKind.PERSONAL if personal else WorkspaceKind.GROUP,
        row["username"] if personal else row["group_name"],
        row["user_id"] if personal else row["group_id"],
        from_text(row["created"]),
        row["name"],
        bool(row["archived"]),
    )


class Workspaces:
    """Workspaces and their revisions in one `Database`."""

    def __init__(
        self, db: Database, accounts: Accounts, retention: Retention | None = None
    ) -> None:
        self.db = db
        self.accounts = accounts
        self.retention = retention if retention is not None else AUTOSAVE_RETENTION

    # --- finding workspaces ---------------------------------------------------------------

    def personal(self, user: User) -> Workspace:
        """The user's default workspace (their first one, named "My programs" unless they
        renamed it), created empty on first use."""
        now = to_text(self.db.clock())

        def get(conn: sqlite3.Connection) -> Workspace:
            if conn.execute("SELECT 1 FROM users WHERE id = ?", (user.id,)).fetchone() is None:
                raise NotFound(f"no user {user.username!r}")
            row = conn.execute(
                _WS_SELECT + " WHERE w.user_id = ? ORDER BY w.id LIMIT 1", (user.id,)
            ).fetchone()
            if row is not None:
                return _workspace(row)
            cursor = conn.execute(
                "INSERT INTO workspaces (user_id, created, name) VALUES (?, ?, ?)",
                (user.id, now, DEFAULT_PERSONAL_NAME),
            )
            return _by_id(conn, cursor.lastrowid)

        return self.db.write(get)

    def mine(self, user: User, *, archived: bool = False) -> list[Workspace]:
        """The user's personal workspaces, the default first (created if none); archived
        ones only when asked."""
        default = self.personal(user)
        rows = self.db.read(
            lambda c: c.execute(
                _WS_SELECT + " WHERE w.user_id = ? AND w.archived <= ? ORDER BY w.id",
                (user.id, int(archived)),
            ).fetchall()
        )
        listed = [_workspace(r) for r in rows]
        return listed if listed and listed[0].id == default.id else [default, *listed]

    def create(
        self,
        user: User,
        name: str,
        *,
        program: str = "",
        points: str = "",
        reason: SaveReason = SaveReason.SAVE,
    ) -> Workspace:
        """A new personal workspace of `user` named `name`, empty or holding `program` and
        `points` as its first revision. `AlreadyExists` when the user has one so named."""
        cleaned = clean_name(name)
        check_size("program", program)
        check_size("points", points)
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> Workspace:
            if conn.execute("SELECT 1 FROM users WHERE id = ?", (user.id,)).fetchone() is None:
                raise NotFound(f"no user {user.username!r}")
            if (
                conn.execute("SELECT 1 FROM workspaces WHERE user_id = ?", (user.id,)).fetchone()
                is None
            ):
                # The first workspace is the default one: keep it "My programs".
                conn.execute(
                    "INSERT INTO workspaces (user_id, created, name) VALUES (?, ?, ?)",
                    (user.id, to_text(now), DEFAULT_PERSONAL_NAME),
                )
            _check_free(conn, user.id, cleaned, None)
            cursor = conn.execute(
                "INSERT INTO workspaces (user_id, created, name) VALUES (?, ?, ?)",
                (user.id, to_text(now), cleaned),
            )
            workspace_id = int(cursor.lastrowid or 0)
            if program or points:
                add_revision(
                    conn, self.retention, workspace_id, program, points, 0, user, reason, now, None
                )
            return _by_id(conn, workspace_id)

        return self.db.write(write)

    def rename(self, workspace_id: int, name: str) -> Workspace:
        """Give a workspace a new name (`AlreadyExists` if its owner has one so named)."""
        cleaned = clean_name(name)

        def write(conn: sqlite3.Connection) -> Workspace:
            found = _by_id(conn, workspace_id)
            if found.kind is WorkspaceKind.PERSONAL:
                _check_free(conn, found.owner_id, cleaned, workspace_id)
            conn.execute("UPDATE workspaces SET name = ? WHERE id = ?", (cleaned, workspace_id))
            return _by_id(conn, workspace_id)

        return self.db.write(write)

    def archive(self, workspace_id: int, archived: bool = True) -> Workspace:
        """Hide a personal workspace from the switcher (or bring it back). Nothing is
        deleted: its revisions stay. A user's default workspace and a group's shared one
        are never hidden."""

        def write(conn: sqlite3.Connection) -> Workspace:
            found = _by_id(conn, workspace_id)
            if archived and found.shared:
                raise InvalidValue("archived", "a group's shared workspace stays available")
            first = conn.execute(
                "SELECT min(id) FROM workspaces WHERE user_id = ?", (found.owner_id,)
            ).fetchone()[0]
            if archived and first == workspace_id:
                raise InvalidValue("archived", "your first workspace stays available")
            conn.execute(
                "UPDATE workspaces SET archived = ? WHERE id = ?", (int(archived), workspace_id)
            )
            return _by_id(conn, workspace_id)

        return self.db.write(write)

    def group(self, name: str) -> Workspace:
        """The lab group's shared workspace, created empty on first use."""
        now = to_text(self.db.clock())

        def get(conn: sqlite3.Connection) -> Workspace:
            row = conn.execute("SELECT id FROM groups WHERE name = ?", (name.strip(),)).fetchone()
            if row is None:
                raise NotFound(f"no group {name.strip()!r}")
            conn.execute(
                "INSERT INTO workspaces (group_id, created, name)"
                " SELECT id, ?, name FROM groups WHERE id = ?"
                " ON CONFLICT (group_id) WHERE group_id IS NOT NULL DO NOTHING",
                (now, row["id"]),
            )
            return _workspace(
                conn.execute(_WS_SELECT + " WHERE w.group_id = ?", (row["id"],)).fetchone()
            )

        return self.db.write(get)

    def get(self, workspace_id: int) -> Workspace:
        row = self.db.read(
            lambda c: c.execute(_WS_SELECT + " WHERE w.id = ?", (workspace_id,)).fetchone()
        )
        if row is None:
            raise NotFound(f"no workspace {workspace_id}")
        return _workspace(row)

    def available_to(self, user: User) -> list[Workspace]:
        """The workspaces `user` may open: their own (not archived) and their group's
        (created if needed); staff also see every other one not archived."""
        mine = self.mine(user)
        if user.group is not None:
            mine.append(self.group(user.group))
        if user.role.is_staff:
            rows = self.db.read(
                lambda c: c.execute(_WS_SELECT + " WHERE w.archived = 0 ORDER BY w.id").fetchall()
            )
            ids = {w.id for w in mine}
            mine.extend(_workspace(r) for r in rows if r["id"] not in ids)
        return mine

    @staticmethod
    def is_member(user: User, workspace: Workspace) -> bool:
        """The workspace is the user's own, or their group's (staff may open others' too,
        but only read them until they ask to edit: `melfa.web.staff_edits`)."""
        if workspace.kind is WorkspaceKind.PERSONAL:
            return workspace.owner_id == user.id
        return user.group is not None and user.group.lower() == workspace.owner.lower()

    @classmethod
    def can_access(cls, user: User, workspace: Workspace) -> bool:
        """Owners, members of the owning group, and staff may open it."""
        if user.disabled:
            return False
        return user.role.is_staff or cls.is_member(user, workspace)

    def check_access(self, user: User, workspace: Workspace) -> None:
        """`AccessDenied` unless `can_access`."""
        if not self.can_access(user, workspace):
            raise AccessDenied(
                f"{user.username} may not open the {workspace.kind.value} workspace of "
                f"{workspace.owner}"
            )

    # --- content --------------------------------------------------------------------------

    def state(self, workspace_id: int) -> WorkspaceState:
        """The current content and the revision number to send back with the next save."""

        return self.db.read(lambda conn: self._state(conn, workspace_id))

    @staticmethod
    def _state(conn: sqlite3.Connection, workspace_id: int) -> WorkspaceState:
        ws = conn.execute(_WS_SELECT + " WHERE w.id = ?", (workspace_id,)).fetchone()
        if ws is None:
            raise NotFound(f"no workspace {workspace_id}")
        head = head_revision(conn, workspace_id, ws["head"])
        if head is None:
            return WorkspaceState(_workspace(ws), 0, "", "")
        return WorkspaceState(_workspace(ws), head.number, head.program, head.points)

    def save(
        self,
        workspace_id: int,
        program: str,
        points: str,
        *,
        base: int,
        author: User | None,
        reason: SaveReason = SaveReason.AUTOSAVE,
    ) -> SaveResult:
        """Store new content on top of revision `base` (0 for a never-saved workspace).

        When `base` is not the newest revision, the edit from `base` to this content is
        merged with what was saved since (`merge3`); `SaveConflict` only when revision
        `base` is no longer kept.
        """
        check_size("program", program)
        check_size("points", points)
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> SaveResult:
            return add_revision(
                conn, self.retention, workspace_id, program, points, base, author, reason, now, None
            )

        return self.db.write(write)

    def save_live(
        self,
        workspace_id: int,
        program: str,
        points: str,
        *,
        authors: Sequence[User],
        epoch: str,
        state: bytes,
    ) -> SaveResult:
        """The live document's text as a new autosave revision by everyone who typed in
        it since the last one (its author reads "alice, bob"), with its CRDT state. The live
        document is the workspace while it is open, so no base is checked: saves from
        elsewhere were merged into it first (`web.coedit`)."""
        check_size("program", program)
        check_size("points", points)
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> SaveResult:
            author = authors[0] if authors else None
            result = add_revision(
                conn,
                self.retention,
                workspace_id,
                program,
                points,
                None,
                author,
                SaveReason.AUTOSAVE,
                now,
                None,
            )
            names = ", ".join(dict.fromkeys(a.username for a in authors))
            if result.created and len(authors) > 1:
                conn.execute(
                    "UPDATE revisions SET author = ? WHERE workspace_id = ? AND number = ?",
                    (names, workspace_id, result.revision.number),
                )
                result = SaveResult(replace(result.revision, author=names), created=True)
            doc = LiveDoc(workspace_id, epoch, result.revision.number, state)
            keep_live_doc(conn, doc, to_text(now))
            return result

        return self.db.write(write)

    def live_doc(self, workspace_id: int) -> tuple[LiveDoc | None, WorkspaceState]:
        """The live document's stored state (None before its first save) and the
        workspace's newest revision, read together."""

        def read(conn: sqlite3.Connection) -> tuple[LiveDoc | None, WorkspaceState]:
            return read_live_doc(conn, workspace_id), self._state(conn, workspace_id)

        return self.db.read(read)

    # --- files ----------------------------------------------------------------------------

    def import_file(
        self,
        workspace_id: int,
        filename: str,
        data: bytes | str,
        *,
        base: int,
        author: User | None,
    ) -> SaveResult:
        """Replace the program (`.MB4`) or the points (`.POS`) from a file, as a new revision.

        The other half of the workspace is kept. `WrongExtension`/`TransferError` for a file
        that does not fit, `SaveConflict` as for `save`.
        """
        kind = file_kind(filename)
        program: str | None = None
        points: str | None = None
        if kind is FileKind.PROGRAM:
            program = program_from_file(filename, data)
            check_size("program", program)
        else:
            points = points_from_file(filename, data)
            check_size("points", points)
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> SaveResult:
            ws = conn.execute("SELECT head FROM workspaces WHERE id = ?", (workspace_id,))
            row = ws.fetchone()
            if row is None:
                raise NotFound(f"no workspace {workspace_id}")
            head = head_revision(conn, workspace_id, row["head"])
            new_program = program if program is not None else (head.program if head else "")
            new_points = points if points is not None else (head.points if head else "")
            return add_revision(
                conn,
                self.retention,
                workspace_id,
                new_program,
                new_points,
                base,
                author,
                SaveReason.IMPORT,
                now,
                None,
            )

        return self.db.write(write)

    def export_file(self, workspace_id: int, kind: FileKind) -> ExportedFile:
        """The current program as a numbered `.MB4`, or the points as a `.POS` file."""
        state = self.state(workspace_id)
        stem = state.workspace.name or state.workspace.owner
        if kind is FileKind.PROGRAM:
            return program_to_file(state.program, stem)
        return points_to_file(state.points, stem)

    # --- history --------------------------------------------------------------------------

    def revisions(
        self, workspace_id: int, *, limit: int = 100, before: int | None = None
    ) -> list[RevisionInfo]:
        """History, newest first; `before` a revision number to page further back."""
        return self.db.read(lambda c: list_revisions(c, workspace_id, limit, before))

    def revision(self, workspace_id: int, number: int) -> Revision:
        """One revision with its texts; `NotFound` if it never existed or was thinned."""
        return self.db.read(lambda c: read_revision(c, workspace_id, number))

    def restore(
        self,
        workspace_id: int,
        number: int,
        *,
        author: User | None,
        base: int | None = None,
    ) -> SaveResult:
        """Make revision `number`'s content current again, as a new revision. The
        revision it replaces is kept from thinning from now on.

        With `base`, refused like a save when the workspace moved on meanwhile.
        """
        now = self.db.clock()

        def write(conn: sqlite3.Connection) -> SaveResult:
            old = read_revision(conn, workspace_id, number)
            # The text being replaced stays, whatever thinning comes later: a restore must
            # never be the reason a student's work disappears.
            conn.execute(
                "UPDATE revisions SET kept = 1 WHERE workspace_id = ?"
                " AND number = (SELECT head FROM workspaces WHERE id = ?)",
                (workspace_id, workspace_id),
            )
            return add_revision(
                conn,
                self.retention,
                workspace_id,
                old.program,
                old.points,
                base,
                author,
                SaveReason.RESTORE,
                now,
                number,
            )

        return self.db.write(write)


def _by_id(conn: sqlite3.Connection, workspace_id: int | None) -> Workspace:
    row = conn.execute(_WS_SELECT + " WHERE w.id = ?", (workspace_id,)).fetchone()
    if row is None:
        raise NotFound(f"no workspace {workspace_id}")
    return _workspace(row)


def _check_free(conn: sqlite3.Connection, user_id: int, name: str, keep: int | None) -> None:
    """`AlreadyExists` when the user has another workspace called `name` (without case)."""
    rows = conn.execute("SELECT id, name FROM workspaces WHERE user_id = ?", (user_id,))
    for row in rows.fetchall():
        if row["id"] != keep and row["name"].casefold() == name.casefold():
            raise AlreadyExists(f"you already have a workspace called \u201c{row['name']}\u201d")
