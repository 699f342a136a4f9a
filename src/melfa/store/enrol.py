"""Yearly enrolment from a CSV file (thesis §6.2: "inserts will happen only once every year").

Columns (header row required, any order, case-insensitive): ``username``, ``name``,
``group``, and optionally ``role`` (default student) and ``password`` (generated when
empty). Every row is checked before anything is written; any bad row refuses the whole
file with one error per problem, each with its line number. The import itself is one
transaction: all rows or none.
"""

from __future__ import annotations

import csv
import io
import sqlite3
from dataclasses import dataclass, field

from melfa.store.accounts import Accounts, NewUser, _fetch, _keep_an_admin, insert_user
from melfa.store.accounts import update_fields as _update_fields
from melfa.store.errors import StoreError, UserInputError
from melfa.store.models import Role
from melfa.store.passwords import generate_password
from melfa.store.timeutil import to_text

__all__ = [
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "EnrolRow",
    "EnrolmentError",
    "EnrolmentReport",
    "RowError",
    "enrol",
    "parse_enrolment",
]

REQUIRED_COLUMNS = ("username", "name", "group")
OPTIONAL_COLUMNS = ("role", "password")
_PLACEHOLDER = generate_password()  # stands in for one still to be generated, while checking


@dataclass(frozen=True, slots=True)
class EnrolRow:
    line: int
    user: NewUser
    password_given: bool


@dataclass(frozen=True, slots=True)
class RowError:
    line: int
    message: str

    def __str__(self) -> str:
        return f"line {self.line}: {self.message}"


class EnrolmentError(UserInputError):
    """The file has bad rows; nothing was imported."""

    def __init__(self, errors: list[RowError]) -> None:
        noun = "problem" if len(errors) == 1 else "problems"
        super().__init__(f"{len(errors)} {noun} in the enrolment file; nothing was imported")
        self.errors = tuple(errors)


@dataclass(slots=True)
class EnrolmentReport:
    created: list[str] = field(default_factory=list)
    updated: list[str] = field(default_factory=list)
    skipped: list[str] = field(default_factory=list)
    generated: dict[str, str] = field(default_factory=dict)
    """Username -> generated password, for the hand-out sheet. Shown once, never stored."""
    rows: dict[str, EnrolRow] = field(default_factory=dict)


def parse_enrolment(text: str) -> list[EnrolRow]:
    """Check every row; `EnrolmentError` lists every problem with its line number."""
    reader = csv.reader(io.StringIO(text.removeprefix("\ufeff"), newline=""))
    errors: list[RowError] = []
    rows: list[EnrolRow] = []
    try:
        header = next(reader, None)
    except csv.Error as err:
        raise EnrolmentError([RowError(1, f"not a CSV file: {err}")]) from None
    if header is None:
        raise EnrolmentError([RowError(1, "the file is empty; expected a header row")])
    columns = [h.strip().lower() for h in header]
    missing = [c for c in REQUIRED_COLUMNS if c not in columns]
    unknown = [c for c in columns if c not in REQUIRED_COLUMNS + OPTIONAL_COLUMNS]
    duplicated = sorted({c for c in columns if columns.count(c) > 1})
    if missing or unknown or duplicated:
        parts = []
        if missing:
            parts.append("missing column(s) " + ", ".join(missing))
        if unknown:
            parts.append("unknown column(s) " + ", ".join(unknown))
        if duplicated:
            parts.append("repeated column(s) " + ", ".join(duplicated))
        allowed = ",".join(REQUIRED_COLUMNS) + "[,role][,password]"
        raise EnrolmentError([RowError(1, "; ".join(parts) + f" (expected {allowed})")])
    first_line: dict[str, int] = {}
    end = reader.line_num
    while True:
        start = end + 1
        try:
            record = next(reader, None)
        except csv.Error as err:
            errors.append(RowError(start, f"unreadable CSV: {err}"))
            break
        end = reader.line_num
        if record is None:
            break
        if not any(cell.strip() for cell in record):
            continue
        if len(record) != len(columns):
            errors.append(
                RowError(
                    start, f"{len(record)} fields, expected {len(columns)} ({','.join(columns)})"
                )
            )
            continue
        cells = {c: v.strip() for c, v in zip(columns, record, strict=True)}
        password = cells.get("password", "")
        try:
            user = NewUser.build(
                cells["username"],
                password or _PLACEHOLDER,
                cells.get("role") or Role.STUDENT,
                cells["group"] or None,
                cells["name"],
            )
        except UserInputError as err:
            errors.append(RowError(start, str(err)))
            continue
        if user.username in first_line:
            errors.append(
                RowError(start, f"{user.username!r} is already on line {first_line[user.username]}")
            )
            continue
        first_line[user.username] = start
        rows.append(EnrolRow(start, user, bool(password)))
    if errors:
        raise EnrolmentError(errors)
    return rows


def enrol(
    accounts: Accounts, rows: list[EnrolRow], *, update_existing: bool = False
) -> EnrolmentReport:
    """Create the accounts in one transaction; existing ones skipped or, on request, updated.

    Generated passwords are returned in the report, never stored in clear.
    """
    existing = {u.username for u in accounts.list_users()}
    report = EnrolmentReport(rows={r.user.username: r for r in rows})
    hashes: dict[str, str] = {}
    for row in rows:
        name = row.user.username
        if name in existing and not (update_existing and row.password_given):
            continue
        if row.password_given:
            hashes[name] = accounts.passwords.hash(row.user.password)
        else:
            report.generated[name] = generate_password()
            hashes[name] = accounts.passwords.hash(report.generated[name])
    now = to_text(accounts.db.clock())

    def apply(conn: sqlite3.Connection) -> None:
        for row in rows:
            new = row.user
            current = _fetch(conn, new.username)
            if (current is None) != (new.username not in existing):
                raise StoreError(
                    "accounts changed while importing; nothing was imported, run it again"
                )
            if current is None:
                insert_user(conn, new, hashes[new.username], now)
                report.created.append(new.username)
            elif update_existing:
                if new.role is not Role.ADMIN:
                    _keep_an_admin(
                        conn,
                        current,
                        f"line {row.line}: cannot make {new.username!r} a {new.role.value}",
                    )
                _update_fields(
                    conn,
                    current["id"],
                    new.display_name,
                    new.role,
                    new.group,
                    new.group is None,
                    now,
                )
                if new.username in hashes:
                    conn.execute(
                        "UPDATE users SET password_hash = ? WHERE id = ?",
                        (hashes[new.username], current["id"]),
                    )
                    conn.execute("DELETE FROM sessions WHERE user_id = ?", (current["id"],))
                report.updated.append(new.username)
            else:
                report.skipped.append(new.username)

    try:
        accounts.db.write(apply)
    except BaseException:
        report.created.clear()
        report.updated.clear()
        report.skipped.clear()
        report.generated.clear()
        raise
    return report
