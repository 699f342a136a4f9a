"""schemathesis against the OpenAPI description, signed in as the admin: no server error
(5xx) for any generated request, and every JSON error in the one shape."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from schemathesis.python import asgi

from melfa.web import WebSettings, create_app
from tests.web.conftest import PASSWORDS, fast_service, make_store

SKIP = {"session-logout"}
"""Signing out would end the fuzzing session; logout has its own tests."""


@pytest.mark.slow
def test_no_server_errors(tmp_path: Path) -> None:
    store = make_store(tmp_path / "data")
    app = create_app(
        WebSettings(data_dir=tmp_path / "data", service_config=fast_service()), store=store
    )
    try:
        schema = schemathesis.openapi.from_asgi("/openapi.json", app)
        with asgi.get_client(app) as client:
            login = client.post(
                "/api/session", json={"username": "admin", "password": PASSWORDS["admin"]}
            )
            assert login.status_code == 200
            client.headers["X-CSRF-Token"] = login.json()["csrf_token"]
            checked = 0
            for result in schema.get_all_operations():
                operation = result.ok()
                if operation.definition.raw.get("operationId") in SKIP:
                    continue

                @given(case=operation.as_strategy())
                @settings(
                    max_examples=12,
                    deadline=None,
                    database=None,
                    suppress_health_check=list(HealthCheck),
                )
                def run(case: schemathesis.Case) -> None:
                    response = case.call(session=client)
                    assert response.status_code < 500, (case.path, response.text)
                    if response.status_code >= 400:
                        body = json.loads(response.text)
                        assert set(body["error"]) == {
                            "code",
                            "message",
                            "status",
                            "where",
                            "detail",
                        }
                        assert body["error"]["status"] == response.status_code

                run()
                checked += 1
            assert checked >= 30
    finally:
        asgi.shutdown_lifespans()
        store.close()
