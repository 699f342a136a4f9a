"""Accounts: hashing, authentication, rules, groups, bootstrap, injection."""

from __future__ import annotations

import dataclasses
import sqlite3
from pathlib import Path

import pytest
from argon2 import PasswordHasher

from melfa.store import (
    ADMIN_PASSWORD_ENV,
    AlreadyExists,
    InvalidValue,
    NotFound,
    Role,
    Store,
    User,
    UserInputError,
)
from tests.store.conftest import CHEAP, FakeClock


def _raw_hash(db_path: Path, username: str) -> str:
    conn = sqlite3.connect(db_path)
    try:
        row = conn.execute("SELECT password_hash FROM users WHERE username = ?", (username,))
        return str(row.fetchone()[0])
    finally:
        conn.close()


def test_password_is_stored_as_argon2_hash_only(store: Store, db_path: Path) -> None:
    store.accounts.create_user("ada", "s3cret-pass")
    stored = _raw_hash(db_path, "ada")
    assert stored.startswith("$argon2id$")
    assert "s3cret-pass" not in stored
    assert b"s3cret-pass" not in db_path.read_bytes()


def test_public_user_model_has_no_hash(store: Store) -> None:
    user = store.accounts.create_user("ada", "s3cret-pass", role="instructor", group="G1")
    fields = {f.name for f in dataclasses.fields(User)}
    assert not any("hash" in f or "password" in f for f in fields)
    assert "argon2" not in repr(user)
    assert (user.role, user.group, user.disabled) == (Role.INSTRUCTOR, "G1", False)


def test_authenticate_right_and_wrong(store: Store, clock: FakeClock) -> None:
    store.accounts.create_user("ada", "s3cret-pass")
    assert store.accounts.authenticate("ada", "wrong-pass") is None
    clock.advance(minutes=5)
    user = store.accounts.authenticate("ADA ", "s3cret-pass")
    assert user is not None
    assert user.username == "ada"
    assert user.last_login == clock.now


def test_unknown_user_and_wrong_password_look_the_same(store: Store) -> None:
    store.accounts.create_user("ada", "s3cret-pass")
    store.accounts.create_user("bob", "s3cret-pass")
    store.accounts.set_disabled("bob", True)
    results = [
        store.accounts.authenticate("nobody", "s3cret-pass"),
        store.accounts.authenticate("ada", "wrong-pass"),
        store.accounts.authenticate("bob", "s3cret-pass"),
        store.accounts.authenticate("ada", "x" * 10_000),
    ]
    assert results == [None, None, None, None]


def test_unknown_user_still_costs_a_hash(store: Store, monkeypatch: pytest.MonkeyPatch) -> None:
    calls: list[str] = []
    real = store.passwords.verify

    def counting(stored: str, password: str) -> bool:
        calls.append(password)
        return real(stored, password)

    monkeypatch.setattr(store.passwords, "verify", counting)
    store.accounts.authenticate("nobody", "guess-1234")
    assert calls == ["guess-1234"]


def test_outdated_hash_is_replaced_on_login(db_path: Path, clock: FakeClock) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        store.accounts.create_user("ada", "s3cret-pass")
    old = _raw_hash(db_path, "ada")
    stronger = PasswordHasher(time_cost=2, memory_cost=128, parallelism=1)
    with Store(db_path, clock=clock, hasher=stronger) as store:
        assert store.accounts.authenticate("ada", "wrong-pass") is None
        assert _raw_hash(db_path, "ada") == old  # no rehash on failure
        assert store.accounts.authenticate("ada", "s3cret-pass") is not None
        new = _raw_hash(db_path, "ada")
        assert new != old
        assert "t=2" in new
        assert not stronger.check_needs_rehash(new)
        assert store.accounts.authenticate("ada", "s3cret-pass") is not None


def test_set_password_changes_it(store: Store) -> None:
    store.accounts.create_user("ada", "s3cret-pass")
    store.accounts.set_password("ada", "new-password")
    assert store.accounts.authenticate("ada", "s3cret-pass") is None
    assert store.accounts.authenticate("ada", "new-password") is not None
    with pytest.raises(NotFound):
        store.accounts.set_password("nobody", "new-password")


@pytest.mark.parametrize(
    ("username", "password", "role", "field"),
    [
        ("a", "kettle-moon-1", "student", "username"),
        ("has space", "kettle-moon-1", "student", "username"),
        ("-dash", "kettle-moon-1", "student", "username"),
        ("x" * 33, "kettle-moon-1", "student", "username"),
        ("ada", "short", "student", "password"),
        ("ada", "kettle-moon-1", "wizard", "role"),
    ],
)
def test_rules_refuse_bad_fields(
    store: Store, username: str, password: str, role: str, field: str
) -> None:
    with pytest.raises(InvalidValue) as err:
        store.accounts.create_user(username, password, role=role)
    assert err.value.field == field
    assert store.accounts.list_users() == []


def test_usernames_are_case_insensitive_and_unique(store: Store) -> None:
    store.accounts.create_user("Ada", "kettle-moon-1")
    with pytest.raises(AlreadyExists):
        store.accounts.create_user("ADA", "kettle-moon-2")
    assert [u.username for u in store.accounts.list_users()] == ["ada"]


def test_sql_injection_in_username_is_just_a_bad_name(store: Store) -> None:
    store.accounts.create_user("ada", "s3cret-pass")
    attack = "ada' OR '1'='1' --"
    assert store.accounts.authenticate(attack, "anything") is None
    assert store.accounts.authenticate("x' UNION SELECT 1,2,3,4,5,6,7,8,9 --", "a") is None
    assert store.accounts.find_user(attack) is None
    with pytest.raises(InvalidValue):
        store.accounts.create_user("ada'; DROP TABLE users; --", "kettle-moon-1")
    with pytest.raises(NotFound):
        store.accounts.remove_user("' OR 1=1 --")
    assert [u.username for u in store.accounts.list_users()] == ["ada"]
    # A group name is stored verbatim, not executed.
    with pytest.raises(InvalidValue):
        store.accounts.create_user("bob", "kettle-moon-1", group="G1'); DROP TABLE groups; --")


def test_groups_are_created_on_demand_and_listed(store: Store) -> None:
    store.accounts.create_user("ada", "kettle-moon-1", group="G1")
    store.accounts.create_user("bob", "kettle-moon-1", group="g1")  # same group, any case
    store.accounts.create_user("cy", "kettle-moon-1", group="G2")
    assert [g.name for g in store.accounts.list_groups()] == ["G1", "G2"]
    assert [u.username for u in store.accounts.list_users(group="G1")] == ["ada", "bob"]


def test_list_users_by_role(store: Store) -> None:
    store.accounts.create_user("ada", "kettle-moon-1", role=Role.INSTRUCTOR)
    store.accounts.create_user("bob", "kettle-moon-1")
    assert [u.username for u in store.accounts.list_users(role=Role.STUDENT)] == ["bob"]


def test_remove_user(store: Store) -> None:
    store.accounts.create_user("ada", "kettle-moon-1")
    store.accounts.remove_user("ada")
    assert store.accounts.find_user("ada") is None
    with pytest.raises(NotFound):
        store.accounts.get_user("ada")


def test_last_admin_cannot_be_removed_demoted_or_disabled(store: Store) -> None:
    store.accounts.create_user("root", "kettle-moon-1", role=Role.ADMIN)
    with pytest.raises(UserInputError, match="last enabled admin"):
        store.accounts.remove_user("root")
    with pytest.raises(UserInputError, match="last enabled admin"):
        store.accounts.update_user("root", role=Role.STUDENT)
    with pytest.raises(UserInputError, match="last enabled admin"):
        store.accounts.set_disabled("root", True)
    store.accounts.create_user("root2", "kettle-moon-1", role=Role.ADMIN)
    store.accounts.remove_user("root")
    assert store.accounts.get_user("root2").role is Role.ADMIN


def test_update_user_fields(store: Store) -> None:
    store.accounts.create_user("ada", "kettle-moon-1", group="G1")
    user = store.accounts.update_user("ada", display_name="Ada  Lovelace", group="G2")
    assert (user.display_name, user.group) == ("Ada Lovelace", "G2")
    assert store.accounts.update_user("ada", clear_group=True).group is None


def test_ensure_admin_generates_once(store: Store) -> None:
    password = store.accounts.ensure_admin()
    assert password is not None
    admin = store.accounts.authenticate("admin", password)
    assert admin is not None
    assert admin.role is Role.ADMIN
    assert store.accounts.ensure_admin() is None  # second start: nothing new


def test_ensure_admin_from_environment(store: Store, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(ADMIN_PASSWORD_ENV, "from-the-env")
    assert store.accounts.ensure_admin() is None
    assert store.accounts.authenticate("admin", "from-the-env") is not None


def test_ensure_admin_refuses_a_weak_environment_password(
    store: Store, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv(ADMIN_PASSWORD_ENV, "short")
    with pytest.raises(InvalidValue, match=ADMIN_PASSWORD_ENV):
        store.accounts.ensure_admin()
    assert store.accounts.list_users() == []


def test_accounts_survive_reopening(db_path: Path, clock: FakeClock) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        store.accounts.create_user("ada", "kettle-moon-1", group="G1")
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        user = store.accounts.authenticate("ada", "kettle-moon-1")
        assert user is not None
        assert user.group == "G1"
