"""The committed docs/openapi.json is the app's, ids read as tag-name, docs list routes."""

from __future__ import annotations

import json
import re
from pathlib import Path

from melfa.web import WebSettings, create_app
from tests.web.conftest import Web

ROOT = Path(__file__).resolve().parents[2]


def current_openapi() -> dict[str, object]:
    return create_app(WebSettings()).openapi()


def test_committed_openapi_matches_the_app() -> None:
    committed = json.loads((ROOT / "docs" / "openapi.json").read_text(encoding="utf-8"))
    assert committed == json.loads(json.dumps(current_openapi())), (
        "docs/openapi.json is stale: regenerate it with "
        "python -c 'import json; from melfa.web import create_app; "
        "print(json.dumps(create_app().openapi(), indent=2))' > docs/openapi.json"
    )


def test_operation_ids_are_tag_dash_name() -> None:
    spec = current_openapi()
    ids = [op["operationId"] for item in spec["paths"].values() for op in item.values()]  # type: ignore[attr-defined]
    assert len(ids) == len(set(ids))
    assert all(re.fullmatch(r"[a-z]+-[a-z_]+", i) for i in ids), ids
    assert "robot-run" in ids and "workspaces-save_workspace" in ids


def test_every_route_is_in_docs_api_md() -> None:
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    spec = current_openapi()
    for path, item in spec["paths"].items():  # type: ignore[attr-defined]
        for method in item:
            assert f"{method.upper()} {path}" in text, f"{method.upper()} {path} not in docs/api.md"
    for kind in [
        "hello",
        "state",
        "link",
        "progress",
        "result",
        "lease",
        "jog",
        "queue",
        "ack",
        "error",
        "pong",
        "debug",
        "ping",
        "jog_start",
        "jog_heartbeat",
        "jog_release",
        "hand_toggle",
        "stop",
    ]:
        assert f"`{kind}`" in text, f"WebSocket message {kind} not in docs/api.md"


def test_docs_page_lists_operations_without_cdn(web: Web) -> None:
    page = web.client.get("/docs")
    assert page.status_code == 200
    assert "/api/robot/run" in page.text and "robot-run" in page.text
    assert "cdn" not in page.text.lower() and "<script" not in page.text
    assert web.client.get("/openapi.json").json()["info"]["title"] == "melfa"


def test_schema_names_are_plain() -> None:
    """Two models with one name get module-path names (melfa__web__…): clients read these."""
    names = list(current_openapi()["components"]["schemas"])  # type: ignore[call-overload]
    assert not [n for n in names if "__" in n]
