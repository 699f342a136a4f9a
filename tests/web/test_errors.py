"""Every JSON error has the same shape, and its status matches the HTTP status
(datasette's tests/test_error_shape.py)."""

from __future__ import annotations

from typing import Any

import pytest

from tests.web.conftest import Web, assert_error

CASES: list[tuple[str, str, str, dict[str, Any], int]] = [
    # (who, method, url, request kwargs, status)
    ("nobody", "get", "/api/session", {}, 401),
    ("nobody", "get", "/api/workspaces", {}, 401),
    ("nobody", "post", "/api/robot/run", {}, 401),
    ("nobody", "post", "/api/session", {"json": {"username": "x"}}, 422),
    ("nobody", "post", "/api/session", {"content": b"{not json"}, 422),
    (
        "nobody",
        "post",
        "/api/session",
        {"json": {"username": "ann", "password": "bad-bad-bad"}},
        401,
    ),
    ("nobody", "get", "/api/nothing-here", {}, 404),
    ("nobody", "put", "/api/health", {}, 405),
    ("ann", "get", "/api/users", {}, 403),
    ("ann", "get", "/api/audit", {}, 403),
    ("ann", "post", "/api/lease/takeover", {}, 403),
    ("ann", "get", "/api/workspaces/0", {}, 404),
    ("ann", "get", "/api/workspaces/abc", {}, 422),
    ("ann", "put", "/api/workspaces/1", {"json": {"base": -1, "program": "", "points": ""}}, 422),
    (
        "ann",
        "put",
        "/api/workspaces/1",
        {"json": {"base": 0, "program": "", "points": "", "x": 1}},
        422,
    ),
    ("ann", "post", "/api/check", {"json": {"program": 5}}, 422),
    ("ann", "post", "/api/check", {"json": {"program": "", "workspace_id": 999}}, 404),
    ("ann", "post", "/api/robot/override", {"json": {"percent": 0}}, 422),
    ("ann", "post", "/api/robot/exec", {"json": {"statement": ""}}, 422),
    ("ann", "post", "/api/robot/exec", {"json": {"statement": "MOV P1\nEND"}}, 422),
    ("ann", "post", "/api/robot/hand", {"json": {"action": "wave"}}, 422),
    ("ann", "post", "/api/robot/move", {"json": {"pose": [1, 2, 3, 4, 5, "x"]}}, 422),
    ("ann", "post", "/api/robot/move", {"content": b'{"pose": [NaN, 0, 0, 0, 0, 0]}'}, 422),
    (
        "ann",
        "post",
        "/api/robot/jog-step",
        {"json": {"frame": "up", "axis": 1, "direction": 1}},
        422,
    ),
    ("ann", "get", "/api/audit?limit=100000", {}, 403),
    ("ivy", "get", "/api/audit?limit=100000", {}, 422),
    ("ivy", "get", "/api/audit?since=yesterday", {}, 422),
    ("admin", "delete", "/api/users/nobody-at-all", {}, 404),
    ("admin", "post", "/api/users", {"json": {"username": "ann"}}, 409),
    ("admin", "post", "/api/users", {"json": {"username": "Bad Name!"}}, 422),
    ("admin", "put", "/api/users/ghost/password", {"json": {}}, 404),
]


@pytest.mark.parametrize(("who", "method", "url", "kwargs", "status"), CASES)
def test_error_shape(
    web: Web, who: str, method: str, url: str, kwargs: dict[str, Any], status: int
) -> None:
    if who == "nobody":
        headers = {"content-type": "application/json"} if "content" in kwargs else {}
        response = getattr(web.client, method)(url, headers=headers, **kwargs)
    else:
        browser = getattr(web, who)
        if "content" in kwargs:
            kwargs = {**kwargs, "headers": {"content-type": "application/json"}}
        response = getattr(browser, method)(url, **kwargs)
    assert response.headers["content-type"] == "application/json"
    assert_error(response, status)


def test_validation_error_names_the_field(web: Web) -> None:
    error = assert_error(web.ann.post("/api/robot/override", json={"percent": 400}), 422)
    assert error["code"] == "invalid-request"
    assert error["where"] == {"field": "body.percent"}
    assert "percent" in error["message"]
    assert error["detail"]["problems"][0]["field"] == "body.percent"
