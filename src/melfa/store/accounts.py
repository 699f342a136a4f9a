"""Accounts: users, roles, lab groups, passwords (thesis §6.2, done properly).

The thesis's server built its login query with string formatting and never checked the
password. Here every query is parameterised, passwords are Argon2 hashes, and a failed
login says nothing about why: an unknown user, a wrong password and a disabled account all
give `None`, and all spend one hash verification.
"""

from __future__ import annotations

import os
import re
import sqlite3
import unicodedata
from dataclasses import dataclass

from melfa.store.db import Database
from melfa.store.errors import AlreadyExists, InvalidValue, NotFound, UserInputError
from melfa.store.models import Group, Role, User
from melfa.store.passwords import (
    MAX_PASSWORD_LENGTH,
    Passwords,
    check_password_rules,
    generate_password,
)
from melfa.store.rows import record
from melfa.store.timeutil import from_text, from_text_or_none, to_text

__all__ = [
    "ADMIN_PASSWORD_ENV",
    "ADMIN_USERNAME",
    "MAX_DISPLAY_NAME",
    "Accounts",
    "NewUser",
    "normalize_group",
    "normalize_username",
]

ADMIN_USERNAME = "admin"
ADMIN_PASSWORD_ENV = "MELFA_ADMIN_PASSWORD"
MAX_DISPLAY_NAME = 80

_USERNAME = re.compile(r"[a-z0-9][a-z0-9._-]{1,31}\Z")
_GROUP = re.compile(r"[A-Za-z0-9][A-Za-z0-9._ -]{0,31}\Z")


def normalize_username(username: str) -> str:
    """Lower-case and check a username: 2–32 of ``a-z 0-9 . _ -``, starting with a letter/digit.

    >>> normalize_username(" Alice.B ")
    'alice.b'
    """
    name = username.strip().lower()
    if not _USERNAME.match(name):
        raise InvalidValue(
            "username",
            f"{username!r} is not a valid username: use 2 to 32 of a-z, 0-9, '.', '_', '-', "
            "starting with a letter or digit",
        )
    return name


def normalize_group(group: str) -> str:
    """Check a group name: 1–32 of letters, digits, space, ``. _ -``; case is kept."""
    name = group.strip()
    if not _GROUP.match(name):
        raise InvalidValue(
            "group",
            f"{group!r} is not a valid group name: use 1 to 32 letters, digits, spaces, "
            "'.', '_' or '-', starting with a letter or digit",
        )
    return name


def _normalize_display_name(name: str) -> str:
    name = " ".join(name.split())
    if len(name) > MAX_DISPLAY_NAME:
        raise InvalidValue("name", f"must be at most {MAX_DISPLAY_NAME} characters")
    if any(unicodedata.category(ch).startswith("C") for ch in name):
        raise InvalidValue("name", "must not contain control characters")
    return name


def _role(role: Role | str) -> Role:
    if isinstance(role, Role):
        return role
    try:
        return Role(role.strip().lower())
    except ValueError:
        choices = ", ".join(r.value for r in Role)
        raise InvalidValue("role", f"{role!r} is not a role; use one of {choices}") from None


@dataclass(frozen=True, slots=True)
class NewUser:
    """A validated request to create an account (the Create model; never returned)."""

    username: str
    password: str
    role: Role = Role.STUDENT
    group: str | None = None
    display_name: str = ""

    @classmethod
    def build(
        cls,
        username: str,
        password: str,
        role: Role | str = Role.STUDENT,
        group: str | None = None,
        display_name: str = "",
    ) -> NewUser:
        """Check every field; raise `InvalidValue` naming the first bad one."""
        check_password_rules(password, username)
        return cls(
            normalize_username(username),
            password,
            _role(role),
            normalize_group(group) if group else None,
            _normalize_display_name(display_name),
        )


_USER_SELECT = """
    SELECT u.id, u.username, u.display_name, u.role, g.name AS "group", u.created,
           u.last_login, u.disabled, u.password_hash
    FROM users AS u LEFT JOIN groups AS g ON g.id = u.group_id
"""


def _user(row: sqlite3.Row) -> User:
    return record(
        User, row, role=Role, created=from_text, last_login=from_text_or_none, disabled=bool
    )


def _fetch(conn: sqlite3.Connection, username: str) -> sqlite3.Row | None:
    row: sqlite3.Row | None = conn.execute(
        _USER_SELECT + " WHERE u.username = ?", (username,)
    ).fetchone()
    return row


def _ensure_group(conn: sqlite3.Connection, name: str, now: str) -> int:
    row = conn.execute("SELECT id FROM groups WHERE name = ?", (name,)).fetchone()
    if row is not None:
        return int(row[0])
    cur = conn.execute("INSERT INTO groups (name, created) VALUES (?, ?)", (name, now))
    assert cur.lastrowid is not None
    return cur.lastrowid


def insert_user(conn: sqlite3.Connection, new: NewUser, password_hash: str, now: str) -> User:
    """Insert inside a caller's write transaction (used by bulk enrolment)."""
    if _fetch(conn, new.username) is not None:
        raise AlreadyExists(f"user {new.username!r} already exists")
    group_id = _ensure_group(conn, new.group, now) if new.group else None
    conn.execute(
        "INSERT INTO users (username, display_name, role, group_id, password_hash, created)"
        " VALUES (?, ?, ?, ?, ?, ?)",
        (new.username, new.display_name, new.role.value, group_id, password_hash, now),
    )
    row = _fetch(conn, new.username)
    assert row is not None
    return _user(row)


class Accounts:
    """Users and groups in one `Database`."""

    def __init__(self, db: Database, passwords: Passwords) -> None:
        self.db = db
        self.passwords = passwords

    def _now(self) -> str:
        return to_text(self.db.clock())

    # --- users ----------------------------------------------------------------------------

    def create_user(
        self,
        username: str,
        password: str,
        *,
        role: Role | str = Role.STUDENT,
        group: str | None = None,
        display_name: str = "",
    ) -> User:
        """Create an account (and its group when new); `AlreadyExists` if the name is taken."""
        new = NewUser.build(username, password, role, group, display_name)
        password_hash = self.passwords.hash(new.password)
        now = self._now()
        return self.db.write(lambda conn: insert_user(conn, new, password_hash, now))

    def find_user(self, username: str) -> User | None:
        """The user, or None (also for a name that could never be valid)."""
        key = username.strip().lower()
        row = self.db.read(lambda conn: _fetch(conn, key))
        return None if row is None else _user(row)

    def get_user(self, username: str) -> User:
        """The user; `NotFound` otherwise."""
        user = self.find_user(username)
        if user is None:
            raise NotFound(f"no user {username.strip()!r}")
        return user

    def get_user_by_id(self, user_id: int) -> User | None:
        row = self.db.read(
            lambda conn: conn.execute(_USER_SELECT + " WHERE u.id = ?", (user_id,)).fetchone()
        )
        return None if row is None else _user(row)

    def list_users(self, *, role: Role | None = None, group: str | None = None) -> list[User]:
        """Every user, by username; optionally one role or one group."""
        clauses: list[str] = []
        params: list[str] = []
        if role is not None:
            clauses.append("u.role = ?")
            params.append(role.value)
        if group is not None:
            clauses.append("g.name = ?")
            params.append(group)
        where = (" WHERE " + " AND ".join(clauses)) if clauses else ""
        rows = self.db.read(
            lambda conn: conn.execute(
                _USER_SELECT + where + " ORDER BY u.username", params
            ).fetchall()
        )
        return [_user(r) for r in rows]

    def authenticate(self, username: str, password: str) -> User | None:
        """The user when the password is right and the account enabled; None otherwise.

        Every failure costs one hash verification, so timing does not reveal which names
        exist. A hash made with older parameters is replaced on success.
        """
        if len(password) > MAX_PASSWORD_LENGTH:  # cannot match; do not hash megabytes
            self.passwords.burn(password[:MAX_PASSWORD_LENGTH])
            return None
        key = username.strip().lower()
        row = self.db.read(lambda conn: _fetch(conn, key))
        if row is None:
            self.passwords.burn(password)
            return None
        stored: str = row["password_hash"]
        if not self.passwords.verify(stored, password) or row["disabled"]:
            return None
        new_hash = self.passwords.hash(password) if self.passwords.needs_rehash(stored) else None
        now = self._now()

        def record(conn: sqlite3.Connection) -> None:
            conn.execute("UPDATE users SET last_login = ? WHERE id = ?", (now, row["id"]))
            if new_hash is not None:  # only if nobody changed the password meanwhile
                conn.execute(
                    "UPDATE users SET password_hash = ? WHERE id = ? AND password_hash = ?",
                    (new_hash, row["id"], stored),
                )

        self.db.write(record)
        return self.get_user_by_id(row["id"])

    def set_password(self, username: str, password: str, *, revoke_sessions: bool = True) -> None:
        """Replace the password; by default also sign the user out everywhere."""
        check_password_rules(password, username)
        key = username.strip().lower()
        password_hash = self.passwords.hash(password)

        def change(conn: sqlite3.Connection) -> None:
            cur = conn.execute(
                "UPDATE users SET password_hash = ? WHERE username = ?", (password_hash, key)
            )
            if cur.rowcount == 0:
                raise NotFound(f"no user {username.strip()!r}")
            if revoke_sessions:
                conn.execute(
                    "DELETE FROM sessions"
                    " WHERE user_id = (SELECT id FROM users WHERE username = ?)",
                    (key,),
                )

        self.db.write(change)

    def update_user(
        self,
        username: str,
        *,
        display_name: str | None = None,
        role: Role | str | None = None,
        group: str | None = None,
        clear_group: bool = False,
    ) -> User:
        """Change the given fields; the last enabled admin cannot stop being one. A new
        role signs the user out everywhere."""
        key = username.strip().lower()
        name = None if display_name is None else _normalize_display_name(display_name)
        new_role = None if role is None else _role(role)
        new_group = normalize_group(group) if group else None
        now = self._now()

        def change(conn: sqlite3.Connection) -> User:
            row = _fetch(conn, key)
            if row is None:
                raise NotFound(f"no user {username.strip()!r}")
            if new_role is not None and new_role is not Role.ADMIN:
                _keep_an_admin(conn, row, f"cannot make {key!r} a {new_role.value}")
            update_fields(conn, row["id"], name, new_role, new_group, clear_group, now)
            if new_role is not None and new_role.value != row["role"]:
                # New powers (or fewer) start with a new sign-in: end every session.
                conn.execute("DELETE FROM sessions WHERE user_id = ?", (row["id"],))
            changed = _fetch(conn, key)
            assert changed is not None
            return _user(changed)

        return self.db.write(change)

    def set_disabled(self, username: str, disabled: bool) -> User:
        """Disable (sessions revoked, logins refused) or re-enable an account."""
        key = username.strip().lower()

        def change(conn: sqlite3.Connection) -> User:
            row = _fetch(conn, key)
            if row is None:
                raise NotFound(f"no user {username.strip()!r}")
            if disabled:
                _keep_an_admin(conn, row, f"cannot disable {key!r}")
                conn.execute("DELETE FROM sessions WHERE user_id = ?", (row["id"],))
            conn.execute("UPDATE users SET disabled = ? WHERE id = ?", (int(disabled), row["id"]))
            changed = _fetch(conn, key)
            assert changed is not None
            return _user(changed)

        return self.db.write(change)

    def remove_user(self, username: str) -> None:
        """Delete the account, its sessions and its personal workspace.

        Revisions it saved in group workspaces stay, with the author's name kept.
        """
        key = username.strip().lower()

        def remove(conn: sqlite3.Connection) -> None:
            row = _fetch(conn, key)
            if row is None:
                raise NotFound(f"no user {username.strip()!r}")
            _keep_an_admin(conn, row, f"cannot remove {key!r}")
            conn.execute("DELETE FROM users WHERE id = ?", (row["id"],))

        self.db.write(remove)

    def count_users(self) -> int:
        return int(self.db.read(lambda c: c.execute("SELECT count(*) FROM users").fetchone()[0]))

    # --- groups ---------------------------------------------------------------------------

    def ensure_group(self, name: str) -> Group:
        """The group called `name`, created if new."""
        group = normalize_group(name)
        now = self._now()

        def make(conn: sqlite3.Connection) -> Group:
            gid = _ensure_group(conn, group, now)
            row = conn.execute("SELECT * FROM groups WHERE id = ?", (gid,)).fetchone()
            return Group(row["id"], row["name"], from_text(row["created"]))

        return self.db.write(make)

    def find_group(self, name: str) -> Group | None:
        row = self.db.read(
            lambda c: c.execute("SELECT * FROM groups WHERE name = ?", (name.strip(),)).fetchone()
        )
        return None if row is None else Group(row["id"], row["name"], from_text(row["created"]))

    def list_groups(self) -> list[Group]:
        rows = self.db.read(lambda c: c.execute("SELECT * FROM groups ORDER BY name").fetchall())
        return [Group(r["id"], r["name"], from_text(r["created"])) for r in rows]

    # --- first start ----------------------------------------------------------------------

    def ensure_admin(self, password: str | None = None) -> str | None:
        """Make sure an admin exists; on a fresh database create ``admin``.

        The password is `password`, else ``$MELFA_ADMIN_PASSWORD``, else a generated one,
        which is returned (the only time it is ever visible) for the caller to print.
        Returns None when nothing was generated (an admin existed, or a password was given).
        """
        if self._has_admin():
            return None
        given = password if password is not None else os.environ.get(ADMIN_PASSWORD_ENV)
        generated = None if given else generate_password()
        chosen = given or generated
        assert chosen is not None
        try:
            new = NewUser.build(ADMIN_USERNAME, chosen, Role.ADMIN, None, "Administrator")
        except InvalidValue as err:
            raise InvalidValue(
                "admin password", f"{err} (from {ADMIN_PASSWORD_ENV} or the caller)"
            ) from None
        password_hash = self.passwords.hash(chosen)
        now = self._now()

        def create(conn: sqlite3.Connection) -> bool:
            if _admin_exists(conn):
                return False
            insert_user(conn, new, password_hash, now)
            return True

        created = self.db.write(create)
        return generated if created else None

    def _has_admin(self) -> bool:
        return self.db.read(_admin_exists)


def _admin_exists(conn: sqlite3.Connection) -> bool:
    row = conn.execute("SELECT 1 FROM users WHERE role = 'admin' LIMIT 1").fetchone()
    return row is not None


def _keep_an_admin(conn: sqlite3.Connection, row: sqlite3.Row, what: str) -> None:
    """Refuse to lose the last enabled admin: nobody could manage accounts any more."""
    if row["role"] != Role.ADMIN.value or row["disabled"]:
        return
    others = conn.execute(
        "SELECT count(*) FROM users WHERE role = 'admin' AND disabled = 0 AND id <> ?",
        (row["id"],),
    ).fetchone()[0]
    if others == 0:
        raise UserInputError(f"{what}: it is the last enabled admin account")


def update_fields(
    conn: sqlite3.Connection,
    user_id: int,
    display_name: str | None,
    role: Role | None,
    group: str | None,
    clear_group: bool,
    now: str,
) -> None:
    """Update some fields of one user inside a caller's transaction."""
    if display_name is not None:
        conn.execute("UPDATE users SET display_name = ? WHERE id = ?", (display_name, user_id))
    if role is not None:
        conn.execute("UPDATE users SET role = ? WHERE id = ?", (role.value, user_id))
    if group is not None:
        gid = _ensure_group(conn, group, now)
        conn.execute("UPDATE users SET group_id = ? WHERE id = ?", (gid, user_id))
    elif clear_group:
        conn.execute("UPDATE users SET group_id = NULL WHERE id = ?", (user_id,))
