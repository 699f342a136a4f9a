"""A co-editing task cancelled in the very moment what it waits for arrives still ends.

Python 3.11's ``asyncio.wait_for`` returns what arrived instead and drops the cancellation:
a room's saver cancelled as an edit came in ran on (and the room's close waited for it),
and a socket's reader cancelled as a message came in ran on, applying the edits of a
socket being closed (its session ended, say) for as long as its pings kept coming.

The socket is Starlette's own on an in-memory ASGI channel (`tests.web.asgi_channel`: the
race is one turn of the event loop), the room the app's `CoeditHub` on a real SQLite store."""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import AsyncIterator
from pathlib import Path

from melfa.web.coedit import CoeditHub, CoeditSettings, PeerConn, Room
from melfa.web.coedit_doc import Contents, SharedDoc
from melfa.web.routes.coedit import _first, _receive
from tests.web.asgi_channel import AsgiChannel, turns
from tests.web.conftest import make_store


@contextlib.asynccontextmanager
async def _room(tmp_path: Path) -> AsyncIterator[tuple[CoeditHub, Room, PeerConn]]:
    """Ann's workspace open in a room, as the app opens it; closed (saved) after."""
    with make_store(tmp_path) as store:
        hub = CoeditHub(
            CoeditSettings(),
            asyncio.to_thread,
            store.workspaces.live_doc,
            store.workspaces.save_live,
        )
        ann = store.accounts.get_user("ann")
        room, peer = await hub.enter(store.workspaces.personal(ann).id, ann, True)
        try:
            yield hub, room, peer
        finally:
            await hub.close()


def test_a_room_closing_as_an_edit_comes_in_stops_its_saver(tmp_path: Path) -> None:
    async def main() -> None:
        async with _room(tmp_path) as (hub, room, peer):
            typist = SharedDoc(room.doc.state())
            room.edit(peer, typist.edit_to(Contents("MOV P1\n", "")) or b"")
            await turns()  # the saver waits for a pause in the typing
            saver = room.saver
            assert saver is not None and not saver.done()
            room.edit(peer, typist.edit_to(Contents("MOV P1\nEND\n", "")) or b"")  # an edit...
            saver.cancel()  # ...in the very turn the room closes
            await turns()
            assert saver.cancelled()
            room.saver = None
            await hub.close()  # what was typed is still saved
            assert room.saved == Contents("MOV P1\nEND\n", "")

    asyncio.run(main())


def test_a_reader_cancelled_as_a_message_comes_in_ends(tmp_path: Path) -> None:
    async def main() -> None:
        async with _room(tmp_path) as (hub, room, peer):
            channel = AsgiChannel()
            reader = asyncio.create_task(_receive(await channel.accepted(), hub, room, peer))
            channel.arrives(type="ping")
            await turns()
            assert peer.outbox.qsize() == 1  # it reads: the ping is answered
            channel.arrives(type="ping")  # a message...
            reader.cancel()  # ...in the very turn the socket is closed
            await turns()
            assert reader.cancelled()
            assert peer.outbox.qsize() == 1  # and it read no more

    asyncio.run(main())


def test_a_socket_closed_as_its_hello_comes_in_ends(tmp_path: Path) -> None:
    async def main() -> None:
        async with _room(tmp_path) as (hub, _, _):
            channel = AsgiChannel()
            greeting = asyncio.create_task(_first(await channel.accepted(), hub))
            await turns()
            channel.arrives(type="hello", state_vector="AA==")
            greeting.cancel()
            await turns()
            assert greeting.cancelled()

    asyncio.run(main())
