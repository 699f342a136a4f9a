"""Migrations: named, ordered, recorded, idempotent; edited or unknown ones refused."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from melfa.store import MIGRATIONS, Database, DatabaseError, Migration, Store
from tests.store.conftest import CHEAP, FakeClock


def test_fresh_database_gets_every_migration_in_order(db_path: Path) -> None:
    with Database(db_path) as db:
        assert db.applied_migrations() == [m.name for m in MIGRATIONS]
    names = [m.name for m in MIGRATIONS]
    assert names == sorted(names)
    assert names[:3] == ["0001_accounts", "0002_workspaces", "0003_audit"]


def test_reopening_applies_nothing_twice_and_keeps_data(db_path: Path, clock: FakeClock) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        store.accounts.create_user("ada", "kettle-moon-1")
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        assert store.accounts.get_user("ada").username == "ada"
    conn = sqlite3.connect(db_path)
    rows = conn.execute("SELECT name FROM migrations ORDER BY rowid").fetchall()
    conn.close()
    assert [r[0] for r in rows] == [m.name for m in MIGRATIONS]


def test_wal_mode_and_foreign_keys(db_path: Path) -> None:
    with Database(db_path) as db:
        mode = db.write(lambda c: c.execute("PRAGMA journal_mode").fetchone()[0])
        fks = db.read(lambda c: c.execute("PRAGMA foreign_keys").fetchone()[0])
    assert mode == "wal"
    assert fks == 1


def test_new_migration_is_applied_on_open(db_path: Path) -> None:
    Database(db_path).close()
    extra = Migration("0099_extra", ("CREATE TABLE extra (x INTEGER)",))
    with Database(db_path, migrations=(*MIGRATIONS, extra)) as db:
        assert db.applied_migrations()[-1] == "0099_extra"
        assert db.read(lambda c: c.execute("SELECT count(*) FROM extra").fetchone()[0]) == 0


def test_edited_shipped_migration_is_refused(db_path: Path) -> None:
    Database(db_path).close()
    first = MIGRATIONS[0]
    edited = Migration(first.name, (*first.statements, "CREATE TABLE sneaky (x INTEGER)"))
    with pytest.raises(DatabaseError, match="must never be edited"):
        Database(db_path, migrations=(edited, *MIGRATIONS[1:]))


def test_database_from_a_newer_melfa_is_refused(db_path: Path) -> None:
    extra = Migration("0099_future", ("CREATE TABLE future (x INTEGER)",))
    Database(db_path, migrations=(*MIGRATIONS, extra)).close()
    with pytest.raises(DatabaseError, match="newer melfa"):
        Database(db_path)


def test_failing_migration_leaves_nothing_behind(db_path: Path) -> None:
    Database(db_path).close()
    broken = Migration("0099_broken", ("CREATE TABLE ok_table (x)", "CREATE TABLE ("))
    with pytest.raises(DatabaseError):
        Database(db_path, migrations=(*MIGRATIONS, broken))
    with Database(db_path) as db:
        tables = db.read(
            lambda c: [r[0] for r in c.execute("SELECT name FROM sqlite_master WHERE type='table'")]
        )
        assert "ok_table" not in tables
        assert "0099_broken" not in db.applied_migrations()


def test_missing_directory_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(DatabaseError, match="no such directory"):
        Database(tmp_path / "nope" / "melfa.sqlite3")


def test_database_file_is_private(db_path: Path) -> None:
    import stat

    Database(db_path).close()
    assert stat.S_IMODE(db_path.stat().st_mode) == 0o600


def test_a_file_that_is_not_a_database_is_a_clear_error(db_path: Path) -> None:
    db_path.write_bytes(b"this is not sqlite" * 100)
    with pytest.raises(DatabaseError, match=r"melfa\.sqlite3"):
        Database(db_path)
