"""Live co-editing: one room per open workspace, holding its shared document
(`coedit_doc.SharedDoc`), the editors connected to it (`Peer`s) and its saving.

Issue 26: partners in a group lost each other's lines to the save-conflict dialog and to
saves that silently won. Now every editor of a workspace is a peer of one CRDT document:

* Every edit goes to the server and on to the other peers at once; concurrent edits merge
  by the CRDT, so no line is dropped and no dialog asks anyone to choose.
* The document is saved as the revisions History shows, not per keystroke: once nobody
  has typed for `CoeditSettings.save_after_s`, and at least every `save_every_s` while
  typing goes on; when the last peer leaves; and when a peer asks (``flush``: before a
  download or a load). Each revision names everyone who typed since the one before.
* A peer that was offline keeps its edits; on reconnect the sync exchange (Yjs's) sends
  what each side lacks, and both merge.
* A save from elsewhere (the REST API, the desktop client, a restore, an imported file)
  is merged into the live document (`CoeditHub.rest_write`): the room saves first, the
  store merges the save with that revision line by line, and the difference enters the
  document as an edit every open editor sees.
* Presence: who is here and where their cursor is, named by their signed-in account.

The socket itself (authentication, the messages) is `routes.coedit`.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import uuid
import zlib
from base64 import b64encode
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

from melfa.live.coedit import CoeditServerMessage, Peer, PresenceOut, SavedOut, UpdateOut
from melfa.store import SaveResult, User, WorkspaceState
from melfa.store.live_docs import LiveDoc
from melfa.web.coedit_doc import Contents, SharedDoc

__all__ = ["PEER_COLOURS", "CoeditHub", "CoeditSettings", "PeerConn", "Room"]

_log = logging.getLogger("melfa.web.coedit")

PEER_COLOURS = 8
"""How many peer colours the IDE has (``.peer-0`` … ``.peer-7`` in css/coedit.css)."""

Runner = Callable[..., Awaitable[Any]]


@dataclass(frozen=True, slots=True)
class CoeditSettings:
    """When a live document becomes a revision, and when a silent socket is let go."""

    save_after_s: float = 2.0
    """Quiet time after the last edit before it is saved as a revision."""
    save_every_s: float = 20.0
    """While typing goes on without a pause, a revision at least this often."""
    silent_s: float = 15.0
    """A socket that sends nothing (not even its 5 s ping) this long is closed: a PC that
    went offline leaves the presence list."""
    outbox: int = 512
    """Messages waiting for one slow browser; beyond, its socket is closed (it reconnects
    and syncs what it missed)."""

    def __post_init__(self) -> None:
        if not 0 < self.save_after_s <= self.save_every_s:
            raise ValueError("save_after_s must be positive and at most save_every_s")
        if self.silent_s <= 0:
            raise ValueError("silent_s must be positive")


@dataclass(eq=False)
class PeerConn:
    """One open editor: its account, whether it may edit, its cursor and its outbox."""

    peer: int
    user: User
    writable: bool
    colour: int
    outbox: asyncio.Queue[str]
    anchor: str | None = None
    head: str | None = None
    closed: asyncio.Event = field(default_factory=asyncio.Event)

    def send(self, message: CoeditServerMessage) -> None:
        """Queue for the browser; never waits. A browser this far behind is let go."""
        try:
            self.outbox.put_nowait(message.model_dump_json())
        except asyncio.QueueFull:
            self.closed.set()

    def out(self) -> Peer:
        return Peer(
            peer=self.peer,
            user=self.user.username,
            colour=self.colour,
            writable=self.writable,
            anchor=self.anchor,
            head=self.head,
        )


class Room:
    """One workspace's live document and its peers."""

    def __init__(
        self,
        hub: CoeditHub,
        workspace_id: int,
        doc: SharedDoc,
        epoch: str,
        revision: int,
        saved: Contents,
    ) -> None:
        self.hub = hub
        self.workspace_id = workspace_id
        self.doc = doc
        self.epoch = epoch
        self.revision = revision
        self.saved = saved
        """The texts of revision ``revision``."""
        self.peers: dict[int, PeerConn] = {}
        self.authors: dict[str, User] = {}
        """Who typed since the last revision."""
        self.lock = asyncio.Lock()
        self.changed = asyncio.Event()
        self.last_edit = 0.0
        self.saver: asyncio.Task[None] | None = None
        self.stored_once = False
        """The document's state is in the store (else a restart would make a new one)."""

    # --- peers ---------------------------------------------------------------------------

    def join(self, user: User, writable: bool) -> PeerConn:
        self.hub.next_peer += 1
        # One colour per person (their second tab shares it), the first free one from
        # their name's: two people in a room never share one while colours last.
        own = next((p.colour for p in self.peers.values() if p.user.id == user.id), None)
        taken = {p.colour for p in self.peers.values()}
        start = zlib.crc32(user.username.encode()) % PEER_COLOURS
        free = (c % PEER_COLOURS for c in range(start, start + PEER_COLOURS))
        colour = own if own is not None else next((c for c in free if c not in taken), start)
        peer = PeerConn(
            self.hub.next_peer,
            user,
            writable,
            colour,
            asyncio.Queue(self.hub.settings.outbox),
        )
        self.peers[peer.peer] = peer
        if self.saver is None:
            self.saver = asyncio.create_task(self._saving(), name=f"coedit-{self.workspace_id}")
        return peer

    def presence(self) -> None:
        message = PresenceOut(peers=[p.out() for p in self.peers.values()])
        for peer in self.peers.values():
            peer.send(message)

    def broadcast(self, message: CoeditServerMessage, *, skip: PeerConn | None = None) -> None:
        for peer in self.peers.values():
            if peer is not skip:
                peer.send(message)

    # --- edits ---------------------------------------------------------------------------

    def edit(self, peer: PeerConn, update: bytes) -> None:
        """A peer's update: applied, sent on to the others, saved later."""
        if not peer.writable:
            return
        if self.doc.apply(update):
            self.broadcast(UpdateOut(update=b64encode(update).decode()), skip=peer)
            self.authors.setdefault(peer.user.username, peer.user)
            self._touched()

    def _touched(self) -> None:
        self.last_edit = asyncio.get_running_loop().time()
        self.changed.set()

    async def _saving(self) -> None:
        """Save after a pause in typing, or every `save_every_s` while it goes on."""
        settings = self.hub.settings
        loop = asyncio.get_running_loop()
        while True:
            await self.changed.wait()
            started = loop.time()
            while True:
                self.changed.clear()
                due = min(self.last_edit + settings.save_after_s, started + settings.save_every_s)
                if due <= loop.time():
                    break
                # asyncio.timeout_at, not asyncio.wait_for: Python 3.11's wait_for
                # returns when an edit comes in the moment the room closes and drops the
                # cancellation, and the saver ran on (the room's close waited for it).
                with contextlib.suppress(TimeoutError):
                    async with asyncio.timeout_at(due):
                        await self.changed.wait()
            try:
                await self.save()
            except Exception:  # the store failed: keep the document, try again later
                _log.exception("could not save live workspace %s", self.workspace_id)
                self._touched()

    async def save(self, *, flushed_by: PeerConn | None = None) -> int:
        """Save the document as a revision if it differs from the last one; its number."""
        async with self.lock:
            return await self._save_locked(flushed_by)

    async def _save_locked(self, flushed_by: PeerConn | None = None) -> int:
        contents = self.doc.contents
        if contents == self.saved and self.stored_once:
            if flushed_by is not None:
                flushed_by.send(SavedOut(revision=self.revision, authors=[], flushed=True))
            return self.revision
        authors = list(self.authors.values())
        self.authors = {}
        result: SaveResult = await self.hub.run(
            self.hub.save_live,
            self.workspace_id,
            contents.program,
            contents.points,
            authors=authors,
            epoch=self.epoch,
            state=self.doc.state(),
        )
        self.revision = result.revision.number
        self.saved = contents
        self.stored_once = True
        names = [a.username for a in authors]
        if result.created:
            self.broadcast(SavedOut(revision=self.revision, authors=names))
        if flushed_by is not None and flushed_by.peer in self.peers:
            flushed_by.send(SavedOut(revision=self.revision, authors=names, flushed=True))
        return self.revision

    def merge_external(self, base: Contents, result: SaveResult) -> None:
        """A save from outside (REST) became ``result`` on top of ``base``, the revision
        this room had just saved: its edit enters the document for every peer."""
        theirs = Contents(result.revision.program, result.revision.points)
        update = self.doc.merge_in(base, theirs)
        self.revision = result.revision.number
        self.saved = theirs
        if update is not None:
            self.broadcast(UpdateOut(update=b64encode(update).decode()))
        if self.doc.contents != theirs:  # peers typed meanwhile: save that later
            self._touched()
        self.broadcast(SavedOut(revision=self.revision, authors=[result.revision.author or ""]))

    async def close(self) -> None:
        if self.saver is not None:
            self.saver.cancel()
            with contextlib.suppress(BaseException):
                await self.saver
        self.saver = None


class CoeditHub:
    """Every live room of the server, opened with the first peer and closed (saved) with
    the last."""

    def __init__(
        self,
        settings: CoeditSettings,
        run: Runner,
        load: Callable[[int], tuple[LiveDoc | None, WorkspaceState]],
        save_live: Callable[..., SaveResult],
    ) -> None:
        self.settings = settings
        self.run = run
        """Runs a blocking store call in the database pool (`WebContext.db`)."""
        self.load = load
        self.save_live = save_live
        self.rooms: dict[int, Room] = {}
        self.opening: dict[int, asyncio.Lock] = {}
        self.next_peer = 0

    async def enter(self, workspace_id: int, user: User, writable: bool) -> tuple[Room, PeerConn]:
        """Join the workspace's room, opening it from the store if nobody is in it."""
        lock = self.opening.setdefault(workspace_id, asyncio.Lock())
        async with lock:
            room = self.rooms.get(workspace_id)
            if room is None:
                room = await self._open(workspace_id)
                self.rooms[workspace_id] = room
            return room, room.join(user, writable)

    async def _open(self, workspace_id: int) -> Room:
        stored: LiveDoc | None
        state: WorkspaceState
        stored, state = await self.run(self.load, workspace_id)
        head = Contents(state.program, state.points)
        if stored is not None:
            doc, epoch = SharedDoc(stored.state), stored.epoch
        else:
            doc, epoch = SharedDoc(), uuid.uuid4().hex
        # Saved elsewhere while nobody had it open (the API, a restore): the revision is
        # what the workspace holds, and enters the document as an edit.
        doc.edit_to(head)
        room = Room(self, workspace_id, doc, epoch, state.revision, head)
        room.stored_once = stored is not None and stored.revision == state.revision
        return room

    async def leave(self, room: Room, peer: PeerConn) -> None:
        """A peer went: the others are told; the last one out saves and closes the room."""
        room.peers.pop(peer.peer, None)
        if room.peers:
            room.presence()
            return
        lock = self.opening.setdefault(room.workspace_id, asyncio.Lock())
        async with lock:
            if room.peers:
                return
            await room.close()
            try:
                await room.save()
            finally:
                if self.rooms.get(room.workspace_id) is room:
                    del self.rooms[room.workspace_id]

    async def rest_write(
        self, workspace_id: int, write: Callable[[], Awaitable[SaveResult]]
    ) -> SaveResult:
        """Run a save from outside the live document (REST: save, restore, import). With
        the workspace open, its document is saved first, so the store merges the incoming
        text with everything typed; then the result enters the document."""
        room = self.rooms.get(workspace_id)
        if room is None:
            return await write()
        async with room.lock:
            await room._save_locked()
            base = room.saved
            result = await write()
            if result.created:
                room.merge_external(base, result)
            return result

    async def close(self) -> None:
        """Server shutdown: every open document saved."""
        for room in list(self.rooms.values()):
            await room.close()
            with contextlib.suppress(Exception):
                await room.save()
        self.rooms.clear()
