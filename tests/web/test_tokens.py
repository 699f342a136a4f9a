"""Personal access tokens on the REST API: made and revoked by their owner in the IDE's
user menu (`/api/tokens`), accepted as `Authorization: Bearer` without CSRF, never a
session cookie's stand-in, dead once revoked."""

from __future__ import annotations

import pytest
from starlette.websockets import WebSocketDisconnect

from tests.web.conftest import Web, assert_error


def test_a_user_makes_lists_uses_and_revokes_a_token(web: Web) -> None:
    made = web.ann.post("/api/tokens", json={"label": "roslibpy"})
    assert made.status_code == 201, made.text
    token = made.json()["token"]
    assert token.startswith("melfa_pat_")
    listed = web.ann.get("/api/tokens").json()["tokens"]
    assert [t["label"] for t in listed] == ["roslibpy"]
    assert token not in str(listed)
    assert web.bob.get("/api/tokens").json()["tokens"] == []  # only one's own

    bearer = {"authorization": f"Bearer {token}"}
    me = web.client.get("/api/session", headers=bearer)
    assert me.status_code == 200 and me.json()["user"]["username"] == "ann"
    # A state-changing request with a token needs no CSRF header (no browser sends it).
    saved = web.client.post("/api/tokens", headers=bearer, json={"label": "second"})
    assert saved.status_code == 201, saved.text

    number = listed[0]["id"]
    assert_error(web.bob.delete(f"/api/tokens/{number}"), 404)
    assert web.ann.delete(f"/api/tokens/{number}").status_code == 200
    assert_error(web.client.get("/api/session", headers=bearer), 401, "bad-token")


def test_a_session_token_is_not_a_bearer_token_and_garbage_is_refused(web: Web) -> None:
    assert_error(
        web.client.get("/api/session", headers={"authorization": f"Bearer {web.ann.token}"}),
        401,
        "bad-token",
    )
    assert_error(
        web.client.get("/api/session", headers={"authorization": "Bearer melfa_pat_nope"}), 401
    )


def test_a_token_in_the_websocket_url_signs_in_from_any_origin(web: Web) -> None:
    token = web.ann.post("/api/tokens", json={"label": "lab page"}).json()["token"]
    headers = {"origin": "http://lab-page.example"}
    with web.client.websocket_connect(f"/api/ws?token={token}", headers=headers) as ws:
        hello = ws.receive_json()
        assert hello["type"] == "hello" and hello["user"] == "ann"
    for bad in (web.ann.token, "melfa_pat_forged"):  # a session token is not one
        with (
            pytest.raises(WebSocketDisconnect) as refused,
            web.client.websocket_connect(f"/api/ws?token={bad}", headers=headers),
        ):
            pass
        assert refused.value.code == 1008


def test_revoking_a_token_closes_its_open_socket_at_once(web: Web) -> None:
    made = web.ann.post("/api/tokens", json={"label": "script"}).json()
    with web.client.websocket_connect(f"/api/ws?token={made['token']}") as ws:
        assert ws.receive_json()["type"] == "hello"
        assert web.ann.delete(f"/api/tokens/{made['info']['id']}").status_code == 200
        with pytest.raises(WebSocketDisconnect):
            for _ in range(500):
                ws.receive_json()
