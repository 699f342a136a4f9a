"""Diagnostics: the same JSON as `melfa check`, with the workspace's points; numbering."""

from __future__ import annotations

from pathlib import Path

from melfa.cli.lang_commands import check_files, read_source
from tests.web.conftest import Web, assert_error

PROGRAM = "SERVO ON\nMOV P1\nMOV P9\nGOTO 99\nEND\n"
POINTS = "DEF POS P1=(300,0,400,180,0,180)(7,0)\nDEF POS PFAR=(3000,0,400,180,0,180)(7,0)\n"


def test_check_matches_melfa_check_json(web: Web, tmp_path: Path) -> None:
    (tmp_path / "p.mb4").write_text(PROGRAM)
    (tmp_path / "p.pos").write_text(POINTS)
    reports = check_files([read_source(tmp_path / "p.mb4"), read_source(tmp_path / "p.pos")])
    cli = [r.to_json()["diagnostics"] for r in reports]
    body = web.ann.post("/api/check", json={"program": PROGRAM, "points": POINTS}).json()
    assert body["program"]["diagnostics"] == cli[0]
    assert body["points"]["diagnostics"] == cli[1]
    assert body["program"]["errors"] >= 1
    messages = " ".join(d["message"] for d in body["points"]["diagnostics"])
    assert "PFAR" in messages  # out of reach: a warning on the points
    assert body["points"]["warnings"] >= 1


def test_check_uses_the_workspaces_points(web: Web) -> None:
    ws = web.ann.get("/api/workspaces").json()["default_id"]
    alone = web.ann.post("/api/check", json={"program": "MOV P1\nEND\n"}).json()
    assert any("P1" in d["message"] for d in alone["program"]["diagnostics"])
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "", "points": POINTS})
    with_ws = web.ann.post(
        "/api/check", json={"program": "MOV P1\nEND\n", "workspace_id": ws}
    ).json()
    assert not any("P1" in d["message"] for d in with_ws["program"]["diagnostics"])
    assert_error(
        web.cat.post("/api/check", json={"program": "", "workspace_id": ws}), 403, "forbidden"
    )


def test_number_and_strip(web: Web) -> None:
    numbered = web.ann.post("/api/number", json={"program": "SERVO ON\n*L\nGOTO *L\n"}).json()
    assert numbered == {"ok": True, "text": "10 SERVO ON\n20 *L\n30 GOTO *L\n", "diagnostics": []}
    stepped = web.ann.post(
        "/api/number", json={"program": "A=1\nB=2\n", "start": 100, "step": 5}
    ).json()
    assert stepped["text"] == "100 A=1\n105 B=2\n"
    stripped = web.ann.post("/api/strip", json={"program": "10 SERVO ON\n20 END\n"}).json()
    assert stripped["ok"] and stripped["text"] == "SERVO ON\nEND\n"
    unsafe = web.ann.post("/api/strip", json={"program": "10 A=1\n10 B=2\n"}).json()
    assert unsafe["ok"] is False and unsafe["text"] == "10 A=1\n10 B=2\n"
    assert unsafe["diagnostics"][0]["severity"] == "error"
    assert_error(web.ann.post("/api/number", json={"program": "", "step": 0}), 422)


def test_check_never_fails_on_odd_text(web: Web) -> None:
    for text in ["\x00\x01", "MOV (((((", "é" * 500, "10 " * 300, "\ud7ff"]:
        response = web.ann.post("/api/check", json={"program": text, "points": text})
        assert response.status_code == 200
    surrogate = web.client.post(
        "/api/check",
        content=b'{"program": "\\ud800"}',
        headers={**web.ann.headers(), "content-type": "application/json"},
    )
    assert_error(surrogate, 422, "invalid-request")
