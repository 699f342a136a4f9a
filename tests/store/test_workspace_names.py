"""Several named personal workspaces per user: create, list, rename, archive; and a
database made before workspaces had names keeps its content and its default workspace."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from melfa.store import (
    DEFAULT_PERSONAL_NAME,
    MAX_NAME_CHARS,
    MIGRATIONS,
    AlreadyExists,
    Database,
    FileKind,
    InvalidValue,
    SaveReason,
    Store,
    User,
)
from tests.store.conftest import CHEAP, FakeClock

PROGRAM = "SERVO ON\nMOV P1\nEND\n"
POINTS = "DEF POS P1=(400.00,0.00,300.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture
def ada(store: Store) -> User:
    return store.accounts.create_user("ada", "kettle-moon-1", group="G1")


def test_first_workspace_is_my_programs_and_stays_the_default(store: Store, ada: User) -> None:
    default = store.workspaces.personal(ada)
    assert default.name == DEFAULT_PERSONAL_NAME and not default.shared
    other = store.workspaces.create(ada, "pyramid")
    assert other.id != default.id and other.name == "pyramid" and other.owner == "ada"
    assert store.workspaces.personal(ada) == default
    assert [w.name for w in store.workspaces.mine(ada)] == [DEFAULT_PERSONAL_NAME, "pyramid"]


def test_creating_before_any_default_makes_the_default_first(store: Store, ada: User) -> None:
    made = store.workspaces.create(ada, "exam practice")
    assert store.workspaces.personal(ada).name == DEFAULT_PERSONAL_NAME
    assert store.workspaces.personal(ada).id < made.id


def test_create_with_content_makes_its_first_revision(store: Store, ada: User) -> None:
    made = store.workspaces.create(
        ada, "pyramid", program=PROGRAM, points=POINTS, reason=SaveReason.IMPORT
    )
    state = store.workspaces.state(made.id)
    assert (state.revision, state.program, state.points) == (1, PROGRAM, POINTS)
    assert store.workspaces.revisions(made.id)[0].reason is SaveReason.IMPORT
    assert store.workspaces.state(store.workspaces.personal(ada).id).program == ""


def test_names_are_unique_per_owner_without_case(store: Store, ada: User) -> None:
    store.workspaces.create(ada, "Pyramid")
    with pytest.raises(AlreadyExists, match="already have a workspace called “Pyramid”"):
        store.workspaces.create(ada, "  pyramid ")
    with pytest.raises(AlreadyExists):
        store.workspaces.create(ada, "my PROGRAMS")
    bob = store.accounts.create_user("bob", "kettle-moon-2")
    assert store.workspaces.create(bob, "pyramid").name == "pyramid"  # another owner


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("", "needs a name"),
        ("   ", "needs a name"),
        ("x" * (MAX_NAME_CHARS + 1), f"at most {MAX_NAME_CHARS}"),
        ("tab\x07bell", "control characters"),
    ],
)
def test_bad_names_are_refused_in_plain_words(
    store: Store, ada: User, name: str, message: str
) -> None:
    with pytest.raises(InvalidValue, match=message) as caught:
        store.workspaces.create(ada, name)
    assert caught.value.field == "name"
    assert [w.name for w in store.workspaces.mine(ada)] == [DEFAULT_PERSONAL_NAME]


def test_rename_keeps_content_and_refuses_a_taken_name(store: Store, ada: User) -> None:
    default = store.workspaces.personal(ada)
    store.workspaces.save(default.id, PROGRAM, POINTS, base=0, author=ada)
    store.workspaces.create(ada, "pyramid")
    renamed = store.workspaces.rename(default.id, "  Lab  1  ")
    assert renamed.name == "Lab 1" and renamed.id == default.id
    assert store.workspaces.state(default.id).program == PROGRAM
    assert store.workspaces.rename(default.id, "LAB 1").name == "LAB 1"  # its own name
    with pytest.raises(AlreadyExists):
        store.workspaces.rename(default.id, "Pyramid")
    group = store.workspaces.group("G1")
    assert group.name == "G1" and group.shared
    assert store.workspaces.rename(group.id, "Team pyramid").name == "Team pyramid"
    assert store.workspaces.group("G1").owner == "G1"


def test_archive_hides_but_keeps_everything(store: Store, ada: User) -> None:
    made = store.workspaces.create(ada, "old try", program=PROGRAM)
    hidden = store.workspaces.archive(made.id)
    assert hidden.archived
    assert made.id not in {w.id for w in store.workspaces.available_to(ada)}
    assert made.id in {w.id for w in store.workspaces.mine(ada, archived=True)}
    assert store.workspaces.state(made.id).program == PROGRAM
    assert not store.workspaces.archive(made.id, archived=False).archived
    with pytest.raises(InvalidValue, match="first workspace stays"):
        store.workspaces.archive(store.workspaces.personal(ada).id)
    with pytest.raises(InvalidValue, match="shared workspace stays"):
        store.workspaces.archive(store.workspaces.group("G1").id)


def test_export_file_is_named_after_the_workspace(store: Store, ada: User) -> None:
    made = store.workspaces.create(ada, "Pyramid v2", program=PROGRAM, points=POINTS)
    assert store.workspaces.export_file(made.id, FileKind.PROGRAM).filename == "Pyramid_v2.MB4"
    assert store.workspaces.export_file(made.id, FileKind.POINTS).filename == "Pyramid_v2.POS"


def _old_database(path: Path) -> None:
    """A database exactly as the melfa before named workspaces left it."""
    before = tuple(m for m in MIGRATIONS if m.name < "0008")
    with Database(path, migrations=before) as db:

        def fill(c: sqlite3.Connection) -> None:
            at = "2025-09-01T08:00:00.000000Z"
            c.execute("INSERT INTO groups (id, name, created) VALUES (1, 'Lab-A', ?)", (at,))
            c.execute(
                "INSERT INTO users (id, username, role, group_id, password_hash, created)"
                " VALUES (1, 'ada', 'student', 1, 'x', ?)",
                (at,),
            )
            c.execute(
                "INSERT INTO workspaces (id, user_id, created, head) VALUES (7, 1, ?, 1)", (at,)
            )
            c.execute(
                "INSERT INTO workspaces (id, group_id, created, head) VALUES (8, 1, ?, 0)", (at,)
            )
            c.execute(
                "INSERT INTO revisions (workspace_id, number, author_id, author, created, reason,"
                " program, points) VALUES (7, 1, 1, 'ada', ?, 'save', ?, ?)",
                (at, PROGRAM, POINTS),
            )

        db.write(fill)


def test_a_database_from_before_names_keeps_content_and_default(
    db_path: Path, clock: FakeClock
) -> None:
    _old_database(db_path)
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        assert "0008_workspace_names" in store.db.applied_migrations()
        ada = store.accounts.get_user("ada")
        default = store.workspaces.personal(ada)
        assert (default.id, default.name) == (7, DEFAULT_PERSONAL_NAME)
        state = store.workspaces.state(7)
        assert (state.revision, state.program, state.points) == (1, PROGRAM, POINTS)
        assert store.workspaces.group("Lab-A").name == "Lab-A"
        second = store.workspaces.create(ada, "pyramid")
        assert store.workspaces.personal(ada).id == 7
        assert [w.id for w in store.workspaces.available_to(ada)] == [7, second.id, 8]
