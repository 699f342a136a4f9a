"""What `melfa serve` does for the IDE besides the page itself: a clear page when the
vendored libraries were never built, and the jog speed ceiling in the WebSocket hello."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest
from argon2 import PasswordHasher

from melfa.service import ServiceConfig
from melfa.store import Store
from melfa.web import WebSettings, create_app
from melfa.web.routes import pages

with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # starlette's TestClient prefers httpx2
    from fastapi.testclient import TestClient

PASSWORD = "serving-test-admin"


def _client(tmp_path: Path) -> tuple[TestClient, Store]:
    store = Store.open_dir(tmp_path, hasher=PasswordHasher(time_cost=1, memory_cost=64))
    store.accounts.ensure_admin(PASSWORD)
    settings = WebSettings(data_dir=tmp_path, service_config=ServiceConfig(jog_override_ceiling=7))
    return TestClient(create_app(settings, store=store), base_url="http://testserver"), store


def test_missing_vendor_files_give_a_clear_page(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(pages, "VENDOR", tmp_path / "no-vendor")
    client, store = _client(tmp_path)
    with client:
        client.post("/api/session", json={"username": "admin", "password": PASSWORD})
        reply = client.get("/")
        assert reply.status_code == 503
        assert "scripts/setup" in reply.text and "scripts/build-frontend" in reply.text
        monkeypatch.setattr(pages, "VENDOR", tmp_path)
        (tmp_path / ".stamp").write_text("built\n")
        reply = client.get("/")
        assert reply.status_code == 200 and 'id="editor"' in reply.text
    store.close()


def test_hello_names_the_jog_speed_ceiling(tmp_path: Path) -> None:
    client, store = _client(tmp_path)
    with client:
        client.post("/api/session", json={"username": "admin", "password": PASSWORD})
        with client.websocket_connect("/api/ws") as ws:
            hello = ws.receive_json()
    store.close()
    assert hello["type"] == "hello" and hello["jog_override_ceiling"] == 7
