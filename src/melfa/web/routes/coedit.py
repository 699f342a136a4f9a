"""`/api/workspaces/{id}/live`: the co-editing socket of one workspace (`web.coedit`).

Who may join: the workspace's owner, the members of its group, and staff. Staff join
read-only unless this sign-in chose *Edit as instructor* for it (``PUT
/api/workspaces/{id}/staff-edit``, audited; `web.staff_edits`): an instructor looking at a
student's work never types into it by accident. Signed in by the session cookie like
``/api/ws``, from this site only; the socket closes when the session is revoked. Every
message is a model of `melfa.live.coedit` (docs/coedit-schema.json).
"""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import json
import logging
from base64 import b64decode, b64encode

from fastapi import APIRouter, WebSocket, WebSocketDisconnect
from pydantic import ValidationError

from melfa.live.coedit import (
    COEDIT_CLIENT,
    CursorIn,
    Flush,
    HelloIn,
    PingIn,
    PongOut,
    UpdateIn,
    WelcomeOut,
)
from melfa.store import AccessDenied, NotFound
from melfa.web.coedit import CoeditHub, PeerConn, Room
from melfa.web.config import SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.deps import find_session
from melfa.web.guard import TooManySockets
from melfa.web.ws import GOING_AWAY, POLICY_VIOLATION, origin_allowed

__all__ = ["router"]

router = APIRouter()
_log = logging.getLogger("melfa.web.coedit")

MAX_MESSAGE_CHARS = 4_000_000
"""One message: a whole document's first sync may be large (texts up to 1 M characters)."""


@router.websocket("/api/workspaces/{workspace_id}/live")
async def live_document(websocket: WebSocket, workspace_id: int) -> None:
    context: WebContext = websocket.app.state.web
    if not origin_allowed(websocket, context.settings.allowed_origins):
        await websocket.close(code=POLICY_VIOLATION, reason="origin not allowed")
        return
    token = websocket.cookies.get(SESSION_COOKIE, "")
    session = await find_session(context, token)
    if session is None:
        await websocket.close(code=POLICY_VIOLATION, reason="sign in first")
        return
    user = session.user
    try:
        workspace = await context.db(context.store.workspaces.get, workspace_id)
        context.store.workspaces.check_access(user, workspace)
    except (NotFound, AccessDenied):
        await websocket.close(code=POLICY_VIOLATION, reason="not a workspace you may open")
        return
    edits = context.staff_edits
    writable = edits.may_write(session, workspace)
    ended: list[str] = []
    done = asyncio.Event()

    async def end(reason: str) -> None:
        ended.append(reason)
        done.set()

    try:
        handle = context.guard.open(session, token, end, kind="coedit")
    except TooManySockets as exc:
        await websocket.close(code=POLICY_VIOLATION, reason=str(exc)[:120])
        return
    await websocket.accept()
    hub = context.coedit
    room: Room | None = None
    peer: PeerConn | None = None
    try:
        hello = await _first(websocket, hub)
        if hello is None:
            return
        room, peer = await hub.enter(workspace.id, user, writable)
        same = hello.epoch == room.epoch
        vector = b64decode(hello.state_vector) if same else b"\x00"
        peer.send(
            WelcomeOut(
                peer=peer.peer,
                user=user.username,
                writable=writable,
                visiting=edits.visiting(session, workspace),
                owner=workspace.owner,
                epoch=room.epoch,
                revision=room.revision,
                update=b64encode(room.doc.missing(vector)).decode(),
                state_vector=b64encode(room.doc.state_vector()).decode(),
                merged=same,
            )
        )
        room.presence()
        tasks = [
            asyncio.create_task(_receive(websocket, hub, room, peer)),
            asyncio.create_task(_send(websocket, peer)),
            asyncio.create_task(done.wait()),
            asyncio.create_task(peer.closed.wait()),
        ]
        try:
            await asyncio.wait(tasks, return_when=asyncio.FIRST_COMPLETED)
        finally:
            for task in tasks:
                task.cancel()
            for task in tasks:
                with contextlib.suppress(BaseException):
                    await task
    except (WebSocketDisconnect, RuntimeError):
        pass
    finally:
        context.guard.close(handle)
        if room is not None and peer is not None:
            await asyncio.shield(hub.leave(room, peer))
        with contextlib.suppress(Exception):
            if ended or not handle.alive(dt.datetime.now(dt.UTC)):
                reason = ended[0] if ended else (handle.revoked or "the session ended")
                await websocket.close(code=POLICY_VIOLATION, reason=reason[:120])
            else:
                await websocket.close(code=GOING_AWAY)


async def _first(websocket: WebSocket, hub: CoeditHub) -> HelloIn | None:
    """The client's ``hello``, within `CoeditSettings.silent_s`; None (closed) otherwise."""
    try:
        text = await _text_within(websocket, hub.settings.silent_s)
        message = _parse(text)
    except (TimeoutError, ValueError, KeyError):
        await websocket.close(code=POLICY_VIOLATION, reason="expected hello")
        return None
    if not isinstance(message, HelloIn):
        await websocket.close(code=POLICY_VIOLATION, reason="expected hello")
        return None
    return message


async def _text_within(websocket: WebSocket, seconds: float) -> str:
    """The next text, or TimeoutError after ``seconds`` of silence. Cancelling the caller
    always ends it, even when a message arrives in the same moment: Python 3.11's
    `asyncio.wait_for` then returns the message and drops the cancellation, and the reader
    of a socket being closed (its session ended, say) ran on, applying its edits, for as
    long as its pings kept coming, with the socket's close waiting for it."""
    async with asyncio.timeout(seconds):
        return await websocket.receive_text()


def _parse(text: str) -> HelloIn | UpdateIn | CursorIn | Flush | PingIn:
    if len(text) > MAX_MESSAGE_CHARS:
        raise ValueError("message too large")
    try:
        return COEDIT_CLIENT.validate_python(json.loads(text))
    except (ValidationError, json.JSONDecodeError) as exc:
        raise ValueError(str(exc)) from exc


async def _receive(websocket: WebSocket, hub: CoeditHub, room: Room, peer: PeerConn) -> None:
    while True:
        text = await _text_within(websocket, hub.settings.silent_s)
        try:
            message = _parse(text)
        except ValueError:
            continue  # not ours to act on; the socket stays
        match message:
            case UpdateIn(update=update):
                try:
                    data = b64decode(update, validate=True)
                    room.edit(peer, data)
                except Exception as exc:  # a peer's bytes that are no update
                    _log.warning("update refused from %s: %s", peer.user.username, exc)
            case CursorIn(anchor=anchor, head=head):
                peer.anchor, peer.head = anchor, head
                room.presence()
            case Flush():
                await room.save(flushed_by=peer)
            case PingIn():
                peer.send(PongOut())
            case HelloIn():
                pass


async def _send(websocket: WebSocket, peer: PeerConn) -> None:
    while True:
        await websocket.send_text(await peer.outbox.get())
