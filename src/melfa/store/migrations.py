"""The schema, as named migrations applied in order before first use.

Rules (docs/store.md): a migration that has shipped is never edited. Each is recorded in
`migrations` with a SHA-256 of its statements, and opening a database whose recorded hash
differs, or that holds a migration this melfa does not know (a newer melfa made it), is
refused instead of guessed at. Change the schema by appending a migration.

Each migration is a tuple of single statements run in one transaction (SQLite DDL is
transactional), so a failure leaves the database as it was.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

__all__ = ["MIGRATIONS", "Migration"]


@dataclass(frozen=True, slots=True)
class Migration:
    name: str
    statements: tuple[str, ...]

    @property
    def checksum(self) -> str:
        """Fingerprint of the statements, to detect an edited shipped migration."""
        return hashlib.sha256("\n;\n".join(self.statements).encode()).hexdigest()


_ACCOUNTS = Migration(
    "0001_accounts",
    (
        """
        CREATE TABLE groups (
            id INTEGER PRIMARY KEY,
            name TEXT NOT NULL UNIQUE COLLATE NOCASE,
            created TEXT NOT NULL
        )
        """,
        """
        CREATE TABLE users (
            id INTEGER PRIMARY KEY,
            username TEXT NOT NULL UNIQUE COLLATE NOCASE,
            display_name TEXT NOT NULL DEFAULT '',
            role TEXT NOT NULL CHECK (role IN ('admin', 'instructor', 'student')),
            group_id INTEGER REFERENCES groups (id) ON DELETE SET NULL,
            password_hash TEXT NOT NULL,
            created TEXT NOT NULL,
            last_login TEXT,
            disabled INTEGER NOT NULL DEFAULT 0 CHECK (disabled IN (0, 1))
        )
        """,
        "CREATE INDEX users_group ON users (group_id)",
    ),
)

_WORKSPACES = Migration(
    "0002_workspaces",
    (
        """
        CREATE TABLE workspaces (
            id INTEGER PRIMARY KEY,
            user_id INTEGER REFERENCES users (id) ON DELETE CASCADE,
            group_id INTEGER REFERENCES groups (id) ON DELETE CASCADE,
            created TEXT NOT NULL,
            head INTEGER NOT NULL DEFAULT 0,
            CHECK ((user_id IS NULL) <> (group_id IS NULL))
        )
        """,
        "CREATE UNIQUE INDEX workspaces_user ON workspaces (user_id) WHERE user_id IS NOT NULL",
        "CREATE UNIQUE INDEX workspaces_group ON workspaces (group_id) WHERE group_id IS NOT NULL",
        """
        CREATE TABLE revisions (
            id INTEGER PRIMARY KEY,
            workspace_id INTEGER NOT NULL REFERENCES workspaces (id) ON DELETE CASCADE,
            number INTEGER NOT NULL,
            author_id INTEGER REFERENCES users (id) ON DELETE SET NULL,
            author TEXT,
            created TEXT NOT NULL,
            reason TEXT NOT NULL CHECK (reason IN ('autosave', 'save', 'import', 'restore')),
            program TEXT NOT NULL,
            points TEXT NOT NULL,
            restored_from INTEGER,
            UNIQUE (workspace_id, number)
        )
        """,
        "CREATE INDEX revisions_reason ON revisions (workspace_id, reason, created)",
    ),
)

_AUDIT = Migration(
    "0003_audit",
    (
        """
        CREATE TABLE audit (
            id INTEGER PRIMARY KEY,
            at TEXT NOT NULL,
            actor TEXT,
            role TEXT,
            action TEXT NOT NULL,
            details TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(details)),
            result TEXT NOT NULL
        )
        """,
        "CREATE INDEX audit_at ON audit (at)",
        "CREATE INDEX audit_actor ON audit (actor, id)",
        "CREATE INDEX audit_action ON audit (action, id)",
        """
        CREATE TRIGGER audit_no_update BEFORE UPDATE ON audit
        BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END
        """,
        """
        CREATE TRIGGER audit_no_delete BEFORE DELETE ON audit
        BEGIN SELECT RAISE(ABORT, 'the audit log is append-only'); END
        """,
    ),
)

_SESSIONS = Migration(
    "0004_sessions",
    (
        """
        CREATE TABLE sessions (
            token_hash TEXT PRIMARY KEY,
            user_id INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
            csrf_token TEXT NOT NULL,
            created TEXT NOT NULL,
            expires TEXT NOT NULL,
            last_seen TEXT NOT NULL,
            client_addr TEXT
        )
        """,
        "CREATE INDEX sessions_user ON sessions (user_id)",
        "CREATE INDEX sessions_expires ON sessions (expires)",
        """
        CREATE TABLE login_attempts (
            id INTEGER PRIMARY KEY,
            username TEXT NOT NULL COLLATE NOCASE,
            client_addr TEXT NOT NULL,
            at TEXT NOT NULL,
            success INTEGER NOT NULL CHECK (success IN (0, 1))
        )
        """,
        "CREATE INDEX login_attempts_user ON login_attempts (username, at)",
        "CREATE INDEX login_attempts_addr ON login_attempts (client_addr, at)",
    ),
)

_ACCESS_TOKENS = Migration(
    "0005_access_tokens",
    (
        """
        CREATE TABLE access_tokens (
            id INTEGER PRIMARY KEY,
            token_hash TEXT NOT NULL UNIQUE,
            user_id INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
            label TEXT NOT NULL,
            created TEXT NOT NULL,
            last_used TEXT
        )
        """,
        "CREATE INDEX access_tokens_user ON access_tokens (user_id)",
    ),
)

_LOGIN_ADDRESSES = Migration(
    "0006_login_addresses",
    (
        """
        CREATE TABLE login_addresses (
            username TEXT NOT NULL COLLATE NOCASE,
            client_addr TEXT NOT NULL,
            last_success TEXT NOT NULL,
            PRIMARY KEY (username, client_addr)
        )
        """,
    ),
)

_KEPT_REVISIONS = Migration(
    "0007_kept_revisions",
    ("ALTER TABLE revisions ADD COLUMN kept INTEGER NOT NULL DEFAULT 0 CHECK (kept IN (0, 1))",),
)
"""``kept``: an autosave whose text a restore replaced; thinning never removes it."""

_WORKSPACE_NAMES = Migration(
    "0008_workspace_names",
    (
        "ALTER TABLE workspaces ADD COLUMN name TEXT NOT NULL DEFAULT ''",
        "ALTER TABLE workspaces ADD COLUMN archived INTEGER NOT NULL DEFAULT 0"
        " CHECK (archived IN (0, 1))",
        "UPDATE workspaces SET name = 'My programs' WHERE user_id IS NOT NULL",
        "UPDATE workspaces SET name = (SELECT g.name FROM groups AS g WHERE g.id = group_id)"
        " WHERE group_id IS NOT NULL",
        "DROP INDEX workspaces_user",
        "CREATE UNIQUE INDEX workspaces_user_name ON workspaces (user_id, name COLLATE NOCASE)"
        " WHERE user_id IS NOT NULL",
        "CREATE INDEX workspaces_owner ON workspaces (user_id, id) WHERE user_id IS NOT NULL",
    ),
)
"""Several personal workspaces per user, each named (unique per owner, without case); the
one a user had is named "My programs" and stays their default (the lowest id); a group's
is named after the group. ``archived``: hidden from the switcher, never deleted."""

_ASSIGNMENTS = Migration(
    "0009_assignments",
    (
        """
        CREATE TABLE assignments (
            id INTEGER PRIMARY KEY,
            title TEXT NOT NULL,
            files TEXT NOT NULL CHECK (json_valid(files)),
            group_id INTEGER REFERENCES groups (id) ON DELETE CASCADE,
            variants INTEGER NOT NULL DEFAULT 0 CHECK (variants IN (0, 1)),
            due TEXT,
            attempts INTEGER CHECK (attempts IS NULL OR attempts >= 1),
            author TEXT,
            created TEXT NOT NULL
        )
        """,
        """
        CREATE TABLE assignment_students (
            assignment_id INTEGER NOT NULL REFERENCES assignments (id) ON DELETE CASCADE,
            user_id INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
            seed INTEGER NOT NULL,
            workspace_id INTEGER NOT NULL REFERENCES workspaces (id) ON DELETE CASCADE,
            opened TEXT NOT NULL,
            PRIMARY KEY (assignment_id, user_id)
        )
        """,
        """
        CREATE TABLE submissions (
            id INTEGER PRIMARY KEY,
            assignment_id INTEGER NOT NULL REFERENCES assignments (id) ON DELETE CASCADE,
            user_id INTEGER NOT NULL REFERENCES users (id) ON DELETE CASCADE,
            kind TEXT NOT NULL CHECK (kind IN ('check', 'submit')),
            workspace_id INTEGER NOT NULL REFERENCES workspaces (id) ON DELETE CASCADE,
            revision INTEGER NOT NULL,
            at TEXT NOT NULL,
            passed INTEGER NOT NULL CHECK (passed IN (0, 1)),
            score REAL NOT NULL,
            preflight INTEGER CHECK (preflight IN (0, 1)),
            report TEXT NOT NULL CHECK (json_valid(report))
        )
        """,
        "CREATE INDEX submissions_student ON submissions (assignment_id, user_id, kind, id)",
    ),
)
"""Assignments (the folder's files as JSON: ``assignment.toml`` and what it names, so the
IDE exports the folder it imported), published to the class (``group_id`` NULL) or one
group; each student's variant seed and workspace; every check and submission with its
graded revision and report."""
_RUNS = Migration(
    "0010_runs",
    (
        """
        CREATE TABLE runs (
            id INTEGER PRIMARY KEY,
            target TEXT NOT NULL,
            username TEXT NOT NULL COLLATE NOCASE,
            started TEXT NOT NULL,
            duration REAL NOT NULL,
            outcome TEXT NOT NULL,
            fingerprint TEXT,
            loaded_by TEXT,
            program TEXT,
            frame_count INTEGER NOT NULL,
            frames BLOB,
            simulated BLOB,
            simulated_by TEXT,
            cycle_real REAL,
            cycle_simulated REAL,
            report TEXT NOT NULL DEFAULT '{}',
            kept INTEGER NOT NULL DEFAULT 0 CHECK (kept IN (0, 1))
        )
        """,
        "CREATE INDEX runs_user ON runs (username, started)",
        "CREATE INDEX runs_started ON runs (started)",
        """
        CREATE TABLE simulations (
            username TEXT NOT NULL COLLATE NOCASE,
            fingerprint TEXT NOT NULL,
            created TEXT NOT NULL,
            cycle_time REAL,
            path BLOB NOT NULL,
            PRIMARY KEY (username, fingerprint)
        )
        """,
        "CREATE INDEX simulations_fingerprint ON simulations (fingerprint, created)",
    ),
)
"""Recorded runs on a shared robot (``target``): who, when, how it ended, the program's
fingerprint and text, the encoded samples (``frames``, NULL once thinned) and the simulated
path it is compared with; ``report``: the deviation found (JSON). ``simulations``: each
user's latest passed pre-flight path per fingerprint, what a later real run is compared with."""
_QUEUES = Migration(
    "0011_queues",
    (
        """
        CREATE TABLE queues (
            target TEXT PRIMARY KEY,
            doc TEXT NOT NULL,
            updated TEXT NOT NULL
        )
        """,
    ),
)
"""The queue of each shared robot (``target``: ``lab``): its entries with the exact texts
queued, the turn, paused and attended, as one JSON document (`melfa.service.queue`),
rewritten at every transition so a restart keeps it."""

_SUBMISSION_FINGERPRINTS = Migration(
    "0012_submission_fingerprints",
    ("ALTER TABLE submissions ADD COLUMN fingerprint TEXT",),
)
"""The instructor's gate's fingerprint of a graded text (`melfa.lang.plan.fingerprint_of`):
a recorded run with the same one ran that text on the arm (the class view's column)."""

_LIVE_DOCS = Migration(
    "0013_live_docs",
    (
        """
        CREATE TABLE live_docs (
            workspace_id INTEGER PRIMARY KEY REFERENCES workspaces (id),
            epoch TEXT NOT NULL,
            revision INTEGER NOT NULL,
            state BLOB NOT NULL,
            updated TEXT NOT NULL
        )
        """,
    ),
)
"""The shared document behind a workspace's live co-editing (`web.coedit`): its CRDT state
as one update (``state``), which revision it was last saved as, and an ``epoch`` named when
it was made. A browser that was offline merges its edits into the same document on
reconnect only while the epoch is the same (a new document would duplicate the text)."""

_AUDIT_ROBOT = Migration(
    "0014_audit_robot",
    ("CREATE INDEX audit_robot ON audit (json_extract(details, '$.robot'), id)",),
)
"""Each robot's entries of the audit log (``details.robot``: ``lab`` or ``sim:<user>``),
newest first: the desk's robot log of one robot (`melfa.vocab.robot_log`)."""

_ROBOT_SETTINGS = Migration(
    "0015_robot_settings",
    (
        """
        CREATE TABLE robot_settings (
            target TEXT NOT NULL,
            name TEXT NOT NULL,
            value TEXT NOT NULL,
            by TEXT NOT NULL,
            updated TEXT NOT NULL,
            PRIMARY KEY (target, name)
        )
        """,
    ),
)
"""The live settings staff choose on the instructor's desk for a shared robot (``target``:
``lab``): ``name`` the setting (``require_simulation``, ``lab_networks``), ``value`` its
JSON, who chose it and when; read at start so a restart keeps them (`store.robot_settings`;
the rule against the start-up options: `melfa.service.live_settings`)."""

_SIMULATION_CELLS = Migration(
    "0016_simulation_cells",
    ("ALTER TABLE simulations ADD COLUMN cell TEXT NOT NULL DEFAULT ''",),
)
"""The version of the lab's cell each passed pre-flight ran in (`Cell.digest`; '' for
those kept before): a real run is compared with a simulation in the cell it ran in first."""

_PREFLIGHTS = Migration(
    "0017_preflights",
    (
        """
        CREATE TABLE preflights (
            username TEXT NOT NULL COLLATE NOCASE,
            fingerprint TEXT NOT NULL,
            program_digest TEXT,
            points_digest TEXT,
            cell TEXT NOT NULL,
            created TEXT NOT NULL,
            cycle_time REAL,
            path BLOB NOT NULL,
            PRIMARY KEY (username, fingerprint, cell)
        )
        """,
        "INSERT INTO preflights (username, fingerprint, cell, created, cycle_time, path)"
        " SELECT username, fingerprint, cell, created, cycle_time, path FROM simulations",
        "DROP TABLE simulations",
        "CREATE INDEX preflights_fingerprint ON preflights (fingerprint, created)",
    ),
)
"""The one record of what passed pre-flight (`melfa.store.preflights`), replacing
``simulations``: who, the program and points as sent (``fingerprint``, and the gate's
``program_digest`` and ``points_digest``), the version of the lab's cell it ran in, its
cycle time and path. The instructor's gate reads it at start (a restart keeps every pass)
and a real run is compared with it. One row per user, text and cell: a pass in an earlier
cell is kept, so undoing an edit of the cell makes it count again. Rows kept before have no
digests (they were never kept): they serve the comparison only."""

MIGRATIONS: tuple[Migration, ...] = (
    _ACCOUNTS,
    _WORKSPACES,
    _AUDIT,
    _SESSIONS,
    _ACCESS_TOKENS,
    _LOGIN_ADDRESSES,
    _KEPT_REVISIONS,
    _WORKSPACE_NAMES,
    _ASSIGNMENTS,
    _RUNS,
    _QUEUES,
    _SUBMISSION_FINGERPRINTS,
    _LIVE_DOCS,
    _AUDIT_ROBOT,
    _ROBOT_SETTINGS,
    _SIMULATION_CELLS,
    _PREFLIGHTS,
)
"""Every migration, in the order they apply. Append only."""
