"""Fixtures: a real SQLite file in tmp_path, the app with its lifespan (the in-process
virtual controller), and `Browser`s: one signed-in person each, sharing one TestClient."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pytest
from argon2 import PasswordHasher

with warnings.catch_warnings():
    # starlette prefers httpx2 for its TestClient; httpx is what the lock file has.
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from melfa.service import ServiceConfig
from melfa.store import Store
from melfa.web import CSRF_HEADER, SESSION_COOKIE, WebSettings, create_app

PASSWORDS = {
    "admin": "admin-password-1",
    "ivy": "ivy-password-12",
    "ann": "ann-password-12",
    "bob": "bob-password-12",
    "cat": "cat-password-12",
}
ORIGIN = "http://testserver"


def make_store(path: Path) -> Store:
    store = Store.open_dir(path, hasher=PasswordHasher(time_cost=1, memory_cost=64, parallelism=1))
    if store.accounts.find_user("admin") is None:
        store.accounts.ensure_admin(PASSWORDS["admin"])
        store.accounts.create_user("ivy", PASSWORDS["ivy"], role="instructor")
        store.accounts.create_user("ann", PASSWORDS["ann"], group="G1")
        store.accounts.create_user("bob", PASSWORDS["bob"], group="G1")
        store.accounts.create_user("cat", PASSWORDS["cat"], group="G2")
    return store


@dataclass
class Browser:
    """One signed-in person: their session cookie and CSRF token, sent explicitly."""

    client: TestClient
    username: str
    token: str
    csrf: str

    def headers(self, extra: dict[str, str] | None = None, csrf: bool = True) -> dict[str, str]:
        out = {"cookie": f"{SESSION_COOKIE}={self.token}"}
        if csrf:
            out[CSRF_HEADER] = self.csrf
        out.update(extra or {})
        return out

    def get(self, url: str, **kw: Any) -> Any:
        return self.client.get(url, headers=self.headers(kw.pop("headers", None)), **kw)

    def post(self, url: str, **kw: Any) -> Any:
        return self.client.post(url, headers=self.headers(kw.pop("headers", None)), **kw)

    def put(self, url: str, **kw: Any) -> Any:
        return self.client.put(url, headers=self.headers(kw.pop("headers", None)), **kw)

    def patch(self, url: str, **kw: Any) -> Any:
        return self.client.patch(url, headers=self.headers(kw.pop("headers", None)), **kw)

    def delete(self, url: str, **kw: Any) -> Any:
        return self.client.delete(url, headers=self.headers(kw.pop("headers", None)), **kw)

    def ws(self, origin: str | None = ORIGIN) -> Any:
        headers = {"cookie": f"{SESSION_COOKIE}={self.token}"}
        if origin is not None:
            headers["origin"] = origin
        return self.client.websocket_connect("/api/ws", headers=headers)


@dataclass
class Web:
    client: TestClient
    store: Store
    app: Any
    browsers: dict[str, Browser] = field(default_factory=dict)

    def login(self, username: str) -> Browser:
        response = self.client.post(
            "/api/session", json={"username": username, "password": PASSWORDS[username]}
        )
        assert response.status_code == 200, response.text
        token = response.cookies[SESSION_COOKIE]
        self.client.cookies.clear()
        return Browser(self.client, username, token, response.json()["csrf_token"])

    def __getattr__(self, name: str) -> Browser:
        if name in PASSWORDS:
            if name not in self.browsers:
                self.browsers[name] = self.login(name)
            return self.browsers[name]
        raise AttributeError(name)

    @property
    def service(self) -> Any:
        return self.app.state.web.service


def fast_service() -> ServiceConfig:
    return ServiceConfig(idle_poll_s=0.2)


@pytest.fixture
def store(tmp_path: Path) -> Iterator[Store]:
    with make_store(tmp_path / "data") as store:
        yield store


@pytest.fixture
def web(store: Store, tmp_path: Path) -> Iterator[Web]:
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
    app = create_app(settings, store=store)
    with TestClient(app) as client:
        yield Web(client, store, app)


def assert_error(response: Any, status: int, code: str | None = None) -> dict[str, Any]:
    """The one error shape (datasette's test_error_shape habit)."""
    assert response.status_code == status, response.text
    body = response.json()
    assert set(body) == {"error"}
    error = body["error"]
    assert set(error) == {"code", "message", "status", "where", "detail"}
    assert error["status"] == status
    assert isinstance(error["message"], str) and error["message"]
    if code is not None:
        assert error["code"] == code, error
    return error
