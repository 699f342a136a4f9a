"""melfa.store: SQLite persistence for accounts, sessions, workspaces and the audit log.

Sync `sqlite3`, no ORM: one writer thread, read connections per thread, WAL, named
migrations applied on open (docs/store.md). The web layer uses `AsyncStore`.

>>> import tempfile, pathlib
>>> from argon2 import PasswordHasher
>>> with tempfile.TemporaryDirectory() as tmp:
...     with Store.open_dir(tmp, hasher=PasswordHasher(1, 64, 1)) as store:
...         _ = store.accounts.create_user("ada", "correct horse", group="G1")
...         store.accounts.authenticate("ada", "correct horse").group
'G1'
"""

from melfa.store.accounts import (
    ADMIN_PASSWORD_ENV,
    ADMIN_USERNAME,
    Accounts,
    NewUser,
    normalize_group,
    normalize_username,
)
from melfa.store.assignment_access import allowed, published_to, require
from melfa.store.assignment_models import (
    Assignment,
    AssignmentAction,
    ClassRow,
    Enrolment,
    GradeKind,
    Submission,
    SubmissionSummary,
)
from melfa.store.assignments import AssignmentClosed, Assignments
from melfa.store.audit import AuditLog
from melfa.store.db import Database
from melfa.store.enrol import EnrolmentError, EnrolmentReport, RowError, enrol, parse_enrolment
from melfa.store.errors import (
    AccessDenied,
    AlreadyExists,
    DatabaseError,
    InvalidValue,
    NotFound,
    SaveConflict,
    StoreError,
    TransferError,
    UserInputError,
    WrongExtension,
)
from melfa.store.migrations import MIGRATIONS, Migration
from melfa.store.models import (
    AuditEntry,
    AuditEvent,
    AuditPage,
    Group,
    NewSession,
    RateLimit,
    Revision,
    RevisionInfo,
    Role,
    SaveReason,
    Session,
    User,
    Workspace,
    WorkspaceKind,
    WorkspaceState,
)
from melfa.store.passwords import Passwords, generate_password
from melfa.store.revisions import MAX_TEXT_CHARS, SaveResult
from melfa.store.sessions import LoginAttempts, LoginPolicy, SessionPolicy, Sessions, check_csrf
from melfa.store.store import (
    DATA_ENV,
    DATABASE_FILENAME,
    AsyncStore,
    Store,
    database_path,
    default_data_dir,
)
from melfa.store.thinning import Retention
from melfa.store.tokens import AccessToken, AccessTokens, NewAccessToken, is_access_token
from melfa.store.transfer import (
    ExportedFile,
    FileKind,
    file_kind,
    points_from_file,
    points_to_file,
    program_from_file,
    program_to_file,
)
from melfa.store.workspace_names import DEFAULT_PERSONAL_NAME, MAX_NAME_CHARS, clean_name
from melfa.store.workspaces import Workspaces

__all__ = [
    "ADMIN_PASSWORD_ENV",
    "ADMIN_USERNAME",
    "DATABASE_FILENAME",
    "DATA_ENV",
    "DEFAULT_PERSONAL_NAME",
    "MAX_NAME_CHARS",
    "MAX_TEXT_CHARS",
    "MIGRATIONS",
    "AccessDenied",
    "AccessToken",
    "AccessTokens",
    "Accounts",
    "AlreadyExists",
    "Assignment",
    "AssignmentAction",
    "AssignmentClosed",
    "Assignments",
    "AsyncStore",
    "AuditEntry",
    "AuditEvent",
    "AuditLog",
    "AuditPage",
    "ClassRow",
    "Database",
    "DatabaseError",
    "Enrolment",
    "EnrolmentError",
    "EnrolmentReport",
    "ExportedFile",
    "FileKind",
    "GradeKind",
    "Group",
    "InvalidValue",
    "LoginAttempts",
    "LoginPolicy",
    "Migration",
    "NewAccessToken",
    "NewSession",
    "NewUser",
    "NotFound",
    "Passwords",
    "RateLimit",
    "Retention",
    "Revision",
    "RevisionInfo",
    "Role",
    "RowError",
    "SaveConflict",
    "SaveReason",
    "SaveResult",
    "Session",
    "SessionPolicy",
    "Sessions",
    "Store",
    "StoreError",
    "Submission",
    "SubmissionSummary",
    "TransferError",
    "User",
    "UserInputError",
    "Workspace",
    "WorkspaceKind",
    "WorkspaceState",
    "Workspaces",
    "WrongExtension",
    "allowed",
    "check_csrf",
    "clean_name",
    "database_path",
    "default_data_dir",
    "enrol",
    "file_kind",
    "generate_password",
    "is_access_token",
    "normalize_group",
    "normalize_username",
    "parse_enrolment",
    "points_from_file",
    "points_to_file",
    "program_from_file",
    "program_to_file",
    "published_to",
    "require",
]
