"""Public value types of the store: what callers (web, CLI) get back.

Create-side inputs and public outputs are separate types, so a password hash never
leaves the store: `User` has no hash field at all, and the row type that does
(`accounts._UserRow`) is private.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from typing import Any

__all__ = [
    "AuditEntry",
    "AuditEvent",
    "AuditPage",
    "Group",
    "NewSession",
    "RateLimit",
    "Revision",
    "RevisionInfo",
    "Role",
    "SaveReason",
    "Session",
    "User",
    "Workspace",
    "WorkspaceKind",
    "WorkspaceState",
]


class Role(enum.Enum):
    """What an account may do; the web layer maps roles to permissions."""

    ADMIN = "admin"
    INSTRUCTOR = "instructor"
    STUDENT = "student"

    @property
    def is_staff(self) -> bool:
        """Admins and instructors see every workspace and the audit log."""
        return self is not Role.STUDENT

    def may_manage(self, other: Role) -> bool:
        """Whether this role may add, import, reset the password of or remove an account
        of role ``other`` (the one rule every accounts door asks): admins everyone,
        instructors students, students nobody."""
        if self is Role.ADMIN:
            return True
        return self is Role.INSTRUCTOR and other is Role.STUDENT


@dataclass(frozen=True, slots=True)
class User:
    """An account as the rest of melfa sees it (no password hash)."""

    id: int
    username: str
    display_name: str
    role: Role
    group: str | None
    created: datetime
    last_login: datetime | None
    disabled: bool


@dataclass(frozen=True, slots=True)
class Group:
    """A lab group: students who share a workspace."""

    id: int
    name: str
    created: datetime


@dataclass(frozen=True, slots=True)
class Session:
    """A server-side login session. The cookie token itself is never stored."""

    id: str
    """The token's SHA-256 (hex): safe to log, useless as a cookie."""
    user: User
    csrf_token: str
    created: datetime
    expires: datetime
    last_seen: datetime
    client_addr: str | None


@dataclass(frozen=True, slots=True)
class NewSession:
    """A session just created: `token` goes into the cookie and is shown only this once."""

    token: str
    session: Session


@dataclass(frozen=True, slots=True)
class RateLimit:
    """Whether a login attempt may proceed; truthy when allowed."""

    allowed: bool
    retry_after: timedelta | None = None
    reason: str = ""

    def __bool__(self) -> bool:
        return self.allowed


class WorkspaceKind(enum.Enum):
    PERSONAL = "personal"
    GROUP = "group"


@dataclass(frozen=True, slots=True)
class Workspace:
    """One user's or one group's program and points (the newest revision is the content)."""

    id: int
    kind: WorkspaceKind
    owner: str
    """Username or group name."""
    owner_id: int
    created: datetime
    name: str = ""
    """What the owner calls it ("My programs", "pyramid"); a group's defaults to the group."""
    archived: bool = False
    """Hidden from the switcher; kept with all its history (nothing is ever deleted)."""

    @property
    def shared(self) -> bool:
        """A group's workspace: every member edits the same program."""
        return self.kind is WorkspaceKind.GROUP


class SaveReason(enum.Enum):
    """Why a revision exists; autosaves are thinned, the others kept forever."""

    AUTOSAVE = "autosave"
    SAVE = "save"
    IMPORT = "import"
    RESTORE = "restore"


@dataclass(frozen=True, slots=True)
class RevisionInfo:
    """A revision without its texts, for listing history cheaply."""

    workspace_id: int
    number: int
    author: str | None
    created: datetime
    reason: SaveReason
    restored_from: int | None
    program_chars: int
    points_chars: int


@dataclass(frozen=True, slots=True)
class Revision:
    """One saved state of a workspace. Numbers grow by one per save, per workspace."""

    workspace_id: int
    number: int
    author: str | None
    """Username at the time of saving; None for a system save."""
    created: datetime
    reason: SaveReason
    program: str
    """Editor form: step numbers stripped as `melfa fmt --strip` does."""
    points: str
    restored_from: int | None = None


@dataclass(frozen=True, slots=True)
class WorkspaceState:
    """What an editor loads: the content and the revision to send back with the next save.

    `revision` is 0 for a workspace never saved.
    """

    workspace: Workspace
    revision: int
    program: str
    points: str


@dataclass(frozen=True, slots=True)
class AuditEvent:
    """Something worth keeping a record of: who did what, and how it ended.

    `actor` is a username (None for the system), `details` a JSON-serialisable mapping.
    """

    action: str
    actor: str | None = None
    role: str | None = None
    details: dict[str, Any] = field(default_factory=dict)
    result: str = "ok"
    at: datetime | None = None
    """When it happened; the store's clock when None."""


@dataclass(frozen=True, slots=True)
class AuditEntry:
    """A stored audit event, with its sequence id (the paging cursor)."""

    id: int
    at: datetime
    actor: str | None
    role: str | None
    action: str
    details: dict[str, Any]
    result: str


@dataclass(frozen=True, slots=True)
class AuditPage:
    """One page of audit entries, newest first; pass `next_before` to get the next page."""

    entries: tuple[AuditEntry, ...]
    next_before: int | None
