"""The messages of ``/api/workspaces/{id}/live``: the co-editing socket of one workspace
(`melfa.web.coedit`), as pydantic models; their schema is ``docs/coedit-schema.json``.

The document is a Yjs CRDT (Yjs in the browser, pycrdt on the server): its updates and
state vectors travel as base64 text, opaque to everything but the CRDT. The exchange is
Yjs's own sync: the client says what it has (``hello`` with its state vector), the server
answers with what it lacks and its own state vector (``welcome``), the client sends what
the server lacks (``update``); after that every edit is an ``update`` both ways. Cursors
are Yjs relative positions (base64 too), so they stay on their character while others
type. Who is here (``presence``) names each peer by the account the server signed in,
never by what a client says of itself.

Pure: no I/O.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter

__all__ = [
    "COEDIT_CLIENT",
    "COEDIT_SERVER",
    "CoeditClientMessage",
    "CoeditServerMessage",
    "CursorIn",
    "Flush",
    "HelloIn",
    "Peer",
    "PingIn",
    "PongOut",
    "PresenceOut",
    "SavedOut",
    "UpdateIn",
    "UpdateOut",
    "WelcomeOut",
    "coedit_schema",
]

Base64 = Annotated[str, Field(max_length=2_800_000, description="Bytes as standard base64")]


class _Sent(BaseModel):
    model_config = ConfigDict(extra="ignore", json_schema_extra={"additionalProperties": False})


class _Asked(BaseModel):
    model_config = ConfigDict(extra="ignore")


class HelloIn(_Asked):
    """First message of a client: what its document holds (a Yjs state vector), and the
    epoch of the document it holds, if any (edits made offline merge only into the same
    document)."""

    type: Literal["hello"] = "hello"
    state_vector: Base64
    epoch: str | None = Field(default=None, max_length=64)


class UpdateIn(_Asked):
    """A Yjs update: an edit, or what the server lacked after ``welcome``. Ignored from a
    read-only peer."""

    type: Literal["update"] = "update"
    update: Base64


class CursorIn(_Asked):
    """Where this peer's cursor (``head``) and selection start (``anchor``) are, as Yjs
    relative positions in the program; null when the editor is not focused."""

    type: Literal["cursor"] = "cursor"
    anchor: Base64 | None = None
    head: Base64 | None = None


class Flush(_Asked):
    """Save the document as a revision now (before a download, a load, a sign-out);
    answered by ``saved``."""

    type: Literal["flush"] = "flush"


class PingIn(_Asked):
    """Keeps the socket known alive; a socket silent for `CoeditSettings.silent_s` is
    closed (its peer leaves the presence list)."""

    type: Literal["ping"] = "ping"


CoeditClientMessage = Annotated[
    HelloIn | UpdateIn | CursorIn | Flush | PingIn, Field(discriminator="type")
]
COEDIT_CLIENT = TypeAdapter[CoeditClientMessage](CoeditClientMessage)


class WelcomeOut(_Sent):
    """The answer to ``hello``: who you are, whether you may edit, the document's epoch and
    saved revision, what you lacked (``update``) and what the server holds
    (``state_vector``: send back what it lacks)."""

    type: Literal["welcome"] = "welcome"
    peer: int
    user: str
    writable: bool
    visiting: bool = Field(
        default=False,
        description="Staff reading someone else's workspace (read-only until they choose "
        "Edit as instructor).",
    )
    owner: str = Field(default="", description="Whose workspace it is (a user or a group).")
    epoch: str
    revision: int
    update: Base64
    state_vector: Base64
    merged: bool = Field(
        description="The client's epoch was the document's: its own edits merge in. False: "
        "the client held another document (or none) and starts from this one."
    )


class UpdateOut(_Sent):
    """Someone else's edit (or a save from the API merged in)."""

    type: Literal["update"] = "update"
    update: Base64


class Peer(_Sent):
    """One open editor of the workspace."""

    peer: int
    user: str
    colour: int = Field(ge=0, description="Index into the IDE's peer colours")
    writable: bool
    anchor: Base64 | None = None
    head: Base64 | None = None


class PresenceOut(_Sent):
    """Everyone here now, this client included (its ``peer`` is in ``welcome``)."""

    type: Literal["presence"] = "presence"
    peers: list[Peer]


class SavedOut(_Sent):
    """The document was saved as revision ``revision`` (``authors``: who typed since the
    one before); ``flushed`` when it answers this client's ``flush``."""

    type: Literal["saved"] = "saved"
    revision: int
    authors: list[str]
    flushed: bool = False


class PongOut(_Sent):
    type: Literal["pong"] = "pong"


CoeditServerMessage = Annotated[
    WelcomeOut | UpdateOut | PresenceOut | SavedOut | PongOut, Field(discriminator="type")
]
COEDIT_SERVER = TypeAdapter[CoeditServerMessage](CoeditServerMessage)

_REF = "#/$defs/{model}"


def coedit_schema() -> dict[str, Any]:
    """The schema document (JSON Schema 2020-12), committed as docs/coedit-schema.json.

    Regenerate: ``python -c 'import json; from melfa.live.coedit import coedit_schema;
    print(json.dumps(coedit_schema(), indent=2))' > docs/coedit-schema.json``
    """
    server = COEDIT_SERVER.json_schema(ref_template=_REF)
    client = COEDIT_CLIENT.json_schema(ref_template=_REF)
    defs: dict[str, Any] = {}
    for part in (server, client):
        defs.update(part.pop("$defs", {}))
    defs["CoeditServerMessage"] = {"description": "Everything the server sends.", **server}
    defs["CoeditClientMessage"] = {"description": "Everything the server accepts.", **client}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "melfa /api/workspaces/{id}/live",
        "description": "The messages of a workspace's co-editing socket (docs/api.md).",
        "anyOf": [
            {"$ref": _REF.format(model="CoeditServerMessage")},
            {"$ref": _REF.format(model="CoeditClientMessage")},
        ],
        "$defs": dict(sorted(defs.items())),
    }
