"""Workspaces: autosave revisions, conflicts, restore, sharing, retention, restarts."""

from __future__ import annotations

from pathlib import Path

import pytest

from melfa.store import (
    MAX_TEXT_CHARS,
    AccessDenied,
    InvalidValue,
    NotFound,
    Retention,
    Role,
    SaveConflict,
    SaveReason,
    Store,
    User,
)
from tests.store.conftest import CHEAP, FakeClock

PROGRAM = "SERVO ON\nMOV P1\nHOPEN 1\nEND\n"
POINTS = "DEF POS P1=(400.00,0.00,300.00,180.00,0.00,180.00)(7,0)\n"


@pytest.fixture
def ada(store: Store) -> User:
    return store.accounts.create_user("ada", "kettle-moon-1", group="G1")


def test_new_workspace_is_empty_at_revision_zero(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    state = store.workspaces.state(ws.id)
    assert (state.revision, state.program, state.points) == (0, "", "")
    assert store.workspaces.personal(ada) == ws  # get, not create again


def test_autosave_creates_revisions(store: Store, ada: User, clock: FakeClock) -> None:
    ws = store.workspaces.personal(ada)
    first = store.workspaces.save(ws.id, "SERVO ON\n", "", base=0, author=ada)
    assert first.created
    assert first.revision.number == 1
    clock.advance(seconds=5)
    second = store.workspaces.save(ws.id, PROGRAM, POINTS, base=1, author=ada)
    assert second.revision.number == 2
    assert second.revision.author == "ada"
    assert second.revision.reason is SaveReason.AUTOSAVE
    state = store.workspaces.state(ws.id)
    assert (state.revision, state.program, state.points) == (2, PROGRAM, POINTS)
    history = store.workspaces.revisions(ws.id)
    assert [r.number for r in history] == [2, 1]
    assert history[0].program_chars == len(PROGRAM)
    assert store.workspaces.revision(ws.id, 1).program == "SERVO ON\n"


def test_identical_content_adds_no_revision(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    store.workspaces.save(ws.id, PROGRAM, POINTS, base=0, author=ada)
    again = store.workspaces.save(ws.id, PROGRAM, POINTS, base=1, author=ada)
    assert not again.created
    assert again.revision.number == 1
    empty = store.workspaces.personal(store.accounts.create_user("bob", "kettle-moon-1"))
    assert not store.workspaces.save(empty.id, "", "", base=0, author=None).created
    assert len(store.workspaces.revisions(ws.id)) == 1


def test_stale_save_is_merged_with_what_was_saved_since(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    store.workspaces.save(ws.id, "A\n", "P1=(1,2,3,0,0,0)(7,0)\n", base=0, author=ada)
    store.workspaces.save(ws.id, "A\ntab one\n", "", base=1, author=ada)  # tab 1 -> rev 2
    merged = store.workspaces.save(
        ws.id, "tab two\nA\n", "P2=(0,0,0,0,0,0)(7,0)\n", base=1, author=ada
    )
    assert merged.revision.number == 3
    assert merged.revision.program == "tab two\nA\ntab one\n"
    # tab one deleted P1, tab two changed it to P2: a line both changed keeps both sides.
    assert merged.revision.points == "P2=(0,0,0,0,0,0)(7,0)\n"
    assert store.workspaces.state(ws.id).program == "tab two\nA\ntab one\n"
    # A stale save of what is already there is harmless.
    same = store.workspaces.save(ws.id, "A\ntab one\n", "", base=2, author=ada)
    assert (same.created, same.revision.number) == (False, 3)


def test_save_on_a_revision_no_longer_kept_is_refused(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    store.workspaces.save(ws.id, "A\n", "", base=0, author=ada)
    with pytest.raises(SaveConflict) as err:
        store.workspaces.save(ws.id, "B\n", "", base=5, author=ada)
    assert (err.value.base, err.value.current.number) == (5, 1)
    assert "revision 1" in str(err.value)


def test_restore_creates_a_new_revision(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    store.workspaces.save(ws.id, "first\n", "", base=0, author=ada)
    store.workspaces.save(ws.id, "second\n", POINTS, base=1, author=ada)
    restored = store.workspaces.restore(ws.id, 1, author=ada)
    assert restored.created
    assert restored.revision.number == 3
    assert restored.revision.reason is SaveReason.RESTORE
    assert restored.revision.restored_from == 1
    assert store.workspaces.state(ws.id).program == "first\n"
    # History is intact: 2 is still there.
    assert store.workspaces.revision(ws.id, 2).program == "second\n"
    assert [r.number for r in store.workspaces.revisions(ws.id)] == [3, 2, 1]
    with pytest.raises(NotFound):
        store.workspaces.restore(ws.id, 99, author=ada)
    # Restoring 2 on top of 2 while 3 is current: the edit 2 -> 2 is none, 3 stays.
    assert not store.workspaces.restore(ws.id, 2, author=ada, base=2).created


def test_group_workspace_is_shared_by_members(store: Store, ada: User) -> None:
    bob = store.accounts.create_user("bob", "kettle-moon-1", group="G1")
    eve = store.accounts.create_user("eve", "kettle-moon-1", group="G2")
    teacher = store.accounts.create_user("tom", "kettle-moon-1", role=Role.INSTRUCTOR)
    shared = store.workspaces.group("G1")
    assert store.workspaces.group("g1") == shared
    store.workspaces.save(shared.id, "by ada\n", "", base=0, author=ada)
    bob_view = store.workspaces.state(shared.id)
    assert bob_view.program == "by ada\n"
    store.workspaces.save(shared.id, "by bob\n", "", base=bob_view.revision, author=bob)
    assert [r.author for r in store.workspaces.revisions(shared.id)] == ["bob", "ada"]
    assert store.workspaces.can_access(ada, shared)
    assert store.workspaces.can_access(bob, shared)
    assert store.workspaces.can_access(teacher, shared)
    assert not store.workspaces.can_access(eve, shared)
    with pytest.raises(AccessDenied):
        store.workspaces.check_access(eve, shared)
    assert not store.workspaces.can_access(bob, store.workspaces.personal(ada))
    assert [w.owner for w in store.workspaces.available_to(bob)] == ["bob", "G1"]
    assert {w.owner for w in store.workspaces.available_to(teacher)} >= {"ada", "bob", "G1"}


def test_removed_author_keeps_name_in_group_history(store: Store, ada: User) -> None:
    shared = store.workspaces.group("G1")
    store.workspaces.save(shared.id, "by ada\n", "", base=0, author=ada)
    store.workspaces.personal(ada)
    store.accounts.remove_user("ada")
    assert store.workspaces.revision(shared.id, 1).author == "ada"


def test_oversized_text_is_refused(store: Store, ada: User) -> None:
    ws = store.workspaces.personal(ada)
    with pytest.raises(InvalidValue, match="program"):
        store.workspaces.save(ws.id, "x" * (MAX_TEXT_CHARS + 1), "", base=0, author=ada)


def test_unknown_workspace(store: Store) -> None:
    with pytest.raises(NotFound):
        store.workspaces.state(12345)
    with pytest.raises(NotFound):
        store.workspaces.save(12345, "x", "", base=0, author=None)
    with pytest.raises(NotFound):
        store.workspaces.group("no-such-group")


def test_autosaves_are_thinned_explicit_saves_kept(
    db_path: Path, clock: FakeClock, tmp_path: Path
) -> None:
    retention = Retention(keep_recent=5)
    with Store(db_path, clock=clock, hasher=CHEAP, retention=retention) as store:
        ada = store.accounts.create_user("ada", "kettle-moon-1")
        ws = store.workspaces.personal(ada)
        base = 0
        # Two hours of typing, an autosave every 10 minutes, an explicit save at the start.
        base = store.workspaces.save(
            ws.id, "v0\n", "", base=base, author=ada, reason=SaveReason.SAVE
        ).revision.number
        for i in range(1, 13):
            clock.advance(minutes=10)
            base = store.workspaces.save(
                ws.id, f"v{i}\n", "", base=base, author=ada
            ).revision.number
        history = store.workspaces.revisions(ws.id)
        numbers = [r.number for r in history]
        assert numbers[:5] == [13, 12, 11, 10, 9]  # the newest five autosaves, all kept
        assert 1 in numbers  # the explicit save, kept
        older = [r for r in history if r.number < 9 and r.reason is SaveReason.AUTOSAVE]
        hours = [r.created.strftime("%H") for r in older]
        assert len(hours) == len(set(hours))  # at most one per hour beyond the recent ones
        assert len(older) >= 1
        # A week later, another save thins the old hourly ones to one per day.
        clock.advance(days=8)
        store.workspaces.save(ws.id, "later\n", "", base=base, author=ada)
        old = [
            r
            for r in store.workspaces.revisions(ws.id)
            if r.reason is SaveReason.AUTOSAVE and r.number < 9
        ]
        assert len(old) <= 1


def test_work_survives_a_restart(db_path: Path, clock: FakeClock) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        ada = store.accounts.create_user("ada", "kettle-moon-1")
        ws = store.workspaces.personal(ada)
        store.workspaces.save(ws.id, PROGRAM, POINTS, base=0, author=ada)
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        ada = store.accounts.get_user("ada")
        ws = store.workspaces.personal(ada)
        state = store.workspaces.state(ws.id)
        assert (state.revision, state.program, state.points) == (1, PROGRAM, POINTS)


def test_restore_keeps_every_text_it_replaced_through_any_thinning(
    db_path: Path, clock: FakeClock
) -> None:
    retention = Retention(keep_recent=3)
    with Store(db_path, clock=clock, hasher=CHEAP, retention=retention) as store:
        ada = store.accounts.create_user("ada", "kettle-moon-1")
        ws = store.workspaces.personal(ada)
        base = 0
        seen: set[str] = set()  # every text ada saw restored or replaced
        for round_ in range(4):
            for i in range(10):  # autosaves, minutes apart
                clock.advance(minutes=7)
                text = f"round {round_} edit {i}\n"
                base = store.workspaces.save(ws.id, text, "", base=base, author=ada).revision.number
            old = store.workspaces.revisions(ws.id)[-1].number  # the oldest left
            replaced = store.workspaces.state(ws.id).program
            restored = store.workspaces.restore(ws.id, old, author=ada, base=base).revision
            seen |= {replaced, restored.program}
            base = restored.number
        for _ in range(3):  # days of autosaves after the last restore: thinning runs
            for _minute in range(30):
                clock.advance(minutes=20)
                base = store.workspaces.save(
                    ws.id, f"later {clock.now}\n", "", base=base, author=ada
                ).revision.number
            clock.advance(days=2)
        kept = {
            store.workspaces.revision(ws.id, r.number).program
            for r in store.workspaces.revisions(ws.id)
        }
        assert seen <= kept, sorted(seen - kept)
