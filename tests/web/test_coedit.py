"""Live co-editing through the real app (`web.coedit`, `routes.coedit`): each person is a
pycrdt document speaking the co-editing socket, as the IDE's Yjs does. Partners' lines
merge, presence names the signed-in accounts, staff join read-only unless they ask, an
offline peer's edits merge on reconnect, a save through the API merges into the live
document, and the document is saved as revisions naming who typed."""

from __future__ import annotations

import json
from base64 import b64decode, b64encode
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import pytest
from pycrdt import Doc, Text
from starlette.websockets import WebSocketDisconnect

from melfa.live.coedit import (
    COEDIT_SERVER,
    PresenceOut,
    SavedOut,
    UpdateOut,
    WelcomeOut,
    coedit_schema,
)
from melfa.web import SESSION_COOKIE
from tests.waiting import wait_until
from tests.web.conftest import ORIGIN, Browser, Web

ROOT = Path(__file__).resolve().parents[2]


class Peer:
    """One editor: its own CRDT document and its socket."""

    open: ClassVar[list[Peer]] = []

    def __init__(self, person: Browser, workspace: int, *, edit: bool = False) -> None:
        self.person = person
        self.workspace = workspace
        self.edit = edit
        self.doc: Doc[Text] = Doc()
        self.program = self.doc.get("program", type=Text)
        self.epoch: str | None = None
        self.socket: Any = None
        self.welcome: WelcomeOut | None = None
        self.presence: PresenceOut | None = None
        self.saved: list[SavedOut] = []

    def connect(self) -> Peer:
        url = f"/api/workspaces/{self.workspace}/live" + ("?edit=1" if self.edit else "")
        headers = {"cookie": f"{SESSION_COOKIE}={self.person.token}", "origin": ORIGIN}
        self.socket = self.person.client.websocket_connect(url, headers=headers)
        self.socket.__enter__()
        Peer.open.append(self)
        self.send(type="hello", state_vector=_b64(self.doc.get_state()), epoch=self.epoch)
        welcome = self.read(WelcomeOut)
        self.doc.apply_update(b64decode(welcome.update))
        self.epoch = welcome.epoch
        server_has = b64decode(welcome.state_vector)
        self.send(type="update", update=_b64(self.doc.get_update(server_has)))
        self.welcome = welcome
        return self

    def disconnect(self) -> None:
        if self in Peer.open:
            Peer.open.remove(self)
            self.socket.__exit__(None, None, None)

    def send(self, **message: Any) -> None:
        self.socket.send_text(json.dumps(message))

    def read(self, kind: type[Any]) -> Any:
        """Messages until one of ``kind``; updates are applied on the way."""
        while True:
            message = COEDIT_SERVER.validate_python(self.socket.receive_json())
            if isinstance(message, UpdateOut):
                self.doc.apply_update(b64decode(message.update))
            elif isinstance(message, PresenceOut):
                self.presence = message
            elif isinstance(message, SavedOut):
                self.saved.append(message)
            if isinstance(message, kind):
                return message

    def type(self, index: int, text: str) -> None:
        """Type locally and send the edit."""
        before = self.doc.get_state()
        self.program.insert(len(str(self.program)[:index].encode()), text)
        self.send(type="update", update=_b64(self.doc.get_update(before)))

    def delete(self, index: int, length: int) -> None:
        before = self.doc.get_state()
        at = len(self.text[:index].encode())
        del self.program[at : at + len(self.text[index : index + length].encode())]
        self.send(type="update", update=_b64(self.doc.get_update(before)))

    def offline_type(self, index: int, text: str) -> None:
        self.program.insert(len(str(self.program)[:index].encode()), text)

    def flush(self) -> SavedOut:
        self.send(type="flush")
        while True:
            saved = self.read(SavedOut)
            if saved.flushed:
                return saved

    @property
    def text(self) -> str:
        return str(self.program)


@pytest.fixture(autouse=True)
def _close_peers(web: Web) -> Iterator[None]:
    """A failed test still closes its sockets (the app cannot stop with them open)."""
    yield
    for peer in list(Peer.open):
        peer.disconnect()


def _b64(data: bytes) -> str:
    return b64encode(data).decode()


def _group(web: Web) -> int:
    return int(web.ann.get("/api/workspaces").json()["default_id"])


def test_two_partners_typing_at_once_keep_both_lines(web: Web) -> None:
    ws = _group(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\nEND\n", "points": ""})
    ann = Peer(web.ann, ws).connect()
    bob = Peer(web.bob, ws).connect()
    assert ann.text == bob.text == "MOV P1\nEND\n"
    assert ann.welcome and bob.welcome and ann.welcome.writable and bob.welcome.writable
    # Both type before either has seen the other's edit.
    ann.type(0, "' ann was here\n")
    bob.type(len("MOV P1\n"), "HOPEN 1\n")
    bob.read(UpdateOut)
    ann.read(UpdateOut)
    assert ann.text == bob.text == "' ann was here\nMOV P1\nHOPEN 1\nEND\n"
    saved = ann.flush()
    assert saved.revision == 2
    state = web.bob.get(f"/api/workspaces/{ws}").json()
    assert (state["revision"], state["program"]) == (2, ann.text)
    history = web.ann.get(f"/api/workspaces/{ws}/revisions").json()["revisions"]
    assert history[0]["author"] == "ann, bob" and history[0]["reason"] == "autosave"
    ann.disconnect()
    bob.disconnect()


def test_a_deleted_line_reaches_the_partner(web: Web) -> None:
    """A deletion adds nothing to the CRDT's state vector: it must still go out."""
    ws = _group(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "A\nB\n", "points": ""})
    ann = Peer(web.ann, ws).connect()
    bob = Peer(web.bob, ws).connect()
    ann.delete(0, 2)
    bob.read(UpdateOut)
    assert bob.text == "B\n"


def test_presence_names_the_accounts_with_one_colour_each(web: Web) -> None:
    ws = _group(web)
    ann = Peer(web.ann, ws).connect()
    bob = Peer(web.bob, ws).connect()
    presence = ann.read(PresenceOut)
    while len(presence.peers) < 2:
        presence = ann.read(PresenceOut)
    assert sorted(p.user for p in presence.peers) == ["ann", "bob"]
    assert len({p.colour for p in presence.peers}) == 2
    bob.send(type="cursor", anchor="AAE=", head="AAE=")
    while not any(p.head == "AAE=" for p in ann.read(PresenceOut).peers):
        pass
    bob.disconnect()
    while len(ann.read(PresenceOut).peers) != 1:
        pass
    ann.disconnect()


def test_staff_join_read_only_unless_they_ask_and_others_are_refused(web: Web) -> None:
    ws = _group(web)
    ann = Peer(web.ann, ws).connect()
    ivy = Peer(web.ivy, ws).connect()
    assert ivy.welcome is not None and not ivy.welcome.writable
    ivy.type(0, "instructor's typo\n")
    ann.type(0, "MOV P1\n")
    ivy.read(UpdateOut)
    assert ann.flush().revision == 1
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\n"
    ivy.disconnect()
    asking = Peer(web.ivy, ws, edit=True).connect()  # the browser's word is not enough
    assert asking.welcome is not None and not asking.welcome.writable
    assert asking.welcome.visiting and asking.welcome.owner == "G1"
    asking.disconnect()
    assert web.ivy.put(f"/api/workspaces/{ws}/staff-edit").json()["writable"]
    editing = Peer(web.ivy, ws).connect()
    assert editing.welcome is not None and editing.welcome.writable
    editing.disconnect()
    ann.disconnect()
    cat = Peer(web.cat, ws)  # another group
    try:
        cat.connect()
        raise AssertionError("cat joined G1's workspace")
    except WebSocketDisconnect as closed:
        assert closed.code == 1008


def test_edits_made_offline_merge_on_reconnect(web: Web) -> None:
    ws = _group(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\nEND\n", "points": ""})
    ann = Peer(web.ann, ws).connect()
    bob = Peer(web.bob, ws).connect()
    bob.disconnect()  # bob's PC goes offline, his document stays
    bob.offline_type(len("MOV P1\n"), "DLY 1\n")
    ann.type(0, "HOPEN 1\n")
    bob.connect()  # the same epoch: his edits merge, ann's arrive
    ann.read(UpdateOut)
    assert bob.welcome is not None and bob.welcome.merged
    assert ann.text == bob.text == "HOPEN 1\nMOV P1\nDLY 1\nEND\n"
    ann.flush()
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == ann.text
    ann.disconnect()
    bob.disconnect()


def test_a_save_through_the_api_merges_into_the_live_document(web: Web) -> None:
    """The desktop client saves whole texts on a revision: while partners type live, its
    save is merged into what they have (their unsaved typing included), never over it."""
    ws = _group(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\nEND\n", "points": ""})
    ann = Peer(web.ann, ws).connect()
    ann.type(0, "' live\n")  # not saved yet as a revision
    desktop = web.bob.put(
        f"/api/workspaces/{ws}",
        json={"base": 1, "program": "MOV P1\nMOV P2\nEND\n", "points": "", "reason": "save"},
    )
    assert desktop.status_code == 200
    assert desktop.json()["revision"]["program"] == "' live\nMOV P1\nMOV P2\nEND\n"
    ann.read(UpdateOut)
    assert ann.text == "' live\nMOV P1\nMOV P2\nEND\n"
    # A restore is an edit too: every open editor follows it.
    restored = web.ann.post(f"/api/workspaces/{ws}/revisions/1/restore", json={})
    assert restored.status_code == 200, restored.text
    ann.read(UpdateOut)
    assert ann.text == "MOV P1\nEND\n"
    ann.disconnect()
    wait_until(lambda: web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\nEND\n")


def test_the_document_outlives_the_room(web: Web) -> None:
    """Everyone leaves (the document is saved with its CRDT state); a peer that kept its
    document offline across that still merges into the same document (same epoch)."""
    ws = _group(web)
    ann = Peer(web.ann, ws).connect()
    ann.type(0, "MOV P1\n")
    ann.disconnect()  # the last one out: saved (as the room closes, after the socket)
    wait_until(
        lambda: web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\n",
        what="the revision saved when the room closed",
    )
    ann.offline_type(0, "' offline\n")
    bob = Peer(web.bob, ws).connect()
    bob.type(len(bob.text), "END\n")
    ann.connect()
    bob.read(UpdateOut)
    assert ann.welcome is not None and ann.welcome.merged
    assert ann.text == bob.text == "' offline\nMOV P1\nEND\n"
    bob.disconnect()
    ann.disconnect()


def test_the_committed_schema_is_the_models() -> None:
    """docs/coedit-schema.json is what `melfa.live.coedit` says (regenerate it with the
    command in `coedit_schema`'s docstring)."""
    committed = json.loads((ROOT / "docs" / "coedit-schema.json").read_text(encoding="utf-8"))
    assert committed == coedit_schema()
