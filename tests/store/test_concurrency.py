"""Many threads and an event loop share one store; writes stay serial and complete."""

from __future__ import annotations

import asyncio
import threading
from pathlib import Path

from melfa.store import AsyncStore, SaveConflict, Store
from tests.store.conftest import CHEAP, FakeClock


def test_threads_saving_to_one_workspace_never_lose_a_save(store: Store) -> None:
    ada = store.accounts.create_user("ada", "kettle-moon-1")
    ws = store.workspaces.personal(ada)
    outcomes: list[str] = []
    lock = threading.Lock()

    def tab(name: str) -> None:
        for i in range(10):
            while True:
                state = store.workspaces.state(ws.id)
                # Each tab adds its line to what it read; another may save meanwhile.
                mine = state.program + f"{name} {i}\n"
                try:
                    saved = store.workspaces.save(ws.id, mine, "", base=state.revision, author=ada)
                except SaveConflict:
                    continue  # its base was thinned: not with this retention
                assert f"{name} {i}\n" in saved.revision.program
                with lock:
                    outcomes.append(f"{name} {i}")
                break

    threads = [threading.Thread(target=tab, args=(f"tab{n}",)) for n in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(outcomes) == 40
    assert store.workspaces.state(ws.id).revision == 40
    # Merged, not overwritten: every tab's every line is in the last revision.
    final = store.workspaces.state(ws.id).program.splitlines()
    assert sorted(final) == sorted(outcomes)


def test_async_store_from_an_event_loop(db_path: Path, clock: FakeClock) -> None:
    async def main() -> list[str]:
        with Store(db_path, clock=clock, hasher=CHEAP) as store:
            astore = AsyncStore(store)
            await asyncio.gather(
                *(
                    astore.call(store.accounts.create_user, f"user{i}", "kettle-moon-1")
                    for i in range(8)
                )
            )
            user = await astore.call(store.accounts.authenticate, "user3", "kettle-moon-1")
            assert user is not None
            users = await astore.call(store.accounts.list_users)
            return [u.username for u in users]

    assert asyncio.run(main()) == [f"user{i}" for i in range(8)]


def test_write_async_and_read_async(store: Store) -> None:
    async def main() -> int:
        await store.db.write_async(
            lambda c: c.execute(
                "INSERT INTO groups (name, created) VALUES (?, ?)", ("G9", "2025-01-01")
            )
        )
        return await store.db.read_async(
            lambda c: int(c.execute("SELECT count(*) FROM groups").fetchone()[0])
        )

    assert asyncio.run(main()) == 1


def test_a_second_process_style_handle_sees_committed_writes(
    db_path: Path, clock: FakeClock
) -> None:
    """The CLI and the server open the same file at once."""
    with (
        Store(db_path, clock=clock, hasher=CHEAP) as server,
        Store(db_path, clock=clock, hasher=CHEAP) as cli,
    ):
        cli.accounts.create_user("ada", "kettle-moon-1")
        assert server.accounts.authenticate("ada", "kettle-moon-1") is not None
        server.accounts.set_password("ada", "kettle-moon-2")
        assert cli.accounts.authenticate("ada", "kettle-moon-2") is not None
