"""Property: whatever sequence of saves, stale saves and restores, nothing is lost; a stale
save is the three-way merge of its edit with what was saved since."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.store import Retention, SaveConflict, Store
from melfa.store.merge import merge3
from tests.store.conftest import CHEAP, FakeClock

texts = st.sampled_from(["", "MOV P1\n", "HOPEN 1\n", "END\n"])
ops = st.lists(
    st.one_of(
        st.tuples(st.just("save"), texts, texts),
        st.tuples(st.just("stale"), texts, texts),
        st.tuples(st.just("restore"), st.integers(1, 12), st.just("")),
    ),
    max_size=12,
)


@settings(max_examples=25)
@given(ops)
def test_saves_and_restores_never_lose_or_rewrite(steps: list[tuple[str, object, str]]) -> None:
    clock = FakeClock()
    with (
        tempfile.TemporaryDirectory() as tmp,
        Store(
            Path(tmp) / "m.sqlite3", clock=clock, hasher=CHEAP, retention=Retention(100)
        ) as store,
    ):
        ada = store.accounts.create_user("ada", "kettle-moon-1")
        ws = store.workspaces.personal(ada)
        expected = ("", "")
        history: dict[int, tuple[str, str]] = {}
        for kind, a, b in steps:
            clock.advance(seconds=30)
            head = store.workspaces.state(ws.id).revision
            try:
                if kind == "restore":
                    assert isinstance(a, int)
                    if a not in history:
                        continue
                    result = store.workspaces.restore(ws.id, a, author=ada, base=head)
                    content = history[a]
                else:
                    assert isinstance(a, str)
                    base = head - 1 if kind == "stale" else head
                    result = store.workspaces.save(ws.id, a, b, base=base, author=ada)
                    content = (a, b)
                    if base != head and (a, b) != expected:
                        old = history.get(base, ("", ""))
                        content = (merge3(old[0], expected[0], a), merge3(old[1], expected[1], b))
            except SaveConflict as err:
                assert kind == "stale" and head == 0  # no revision -1
                assert err.current.number == head
                continue
            assert result.created == (content != expected)
            if result.created:
                assert result.revision.number == head + 1
                history[result.revision.number] = content
            expected = content
            state = store.workspaces.state(ws.id)
            assert (state.program, state.points) == expected
        for number, content in history.items():  # every revision still as written
            revision = store.workspaces.revision(ws.id, number)
            assert (revision.program, revision.points) == content
