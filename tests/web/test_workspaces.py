"""Workspaces: autosave, conflicts, history, restore, import/export, access, restarts."""

from __future__ import annotations

from pathlib import Path

from melfa.web import WebSettings, create_app
from tests.web.conftest import TestClient, Web, assert_error, fast_service, make_store

PROGRAM = "SERVO ON\nMOV P1\nHLT\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def _default(web: Web, who: str = "ann") -> int:
    return int(getattr(web, who).get("/api/workspaces").json()["default_id"])


def test_student_sees_own_and_group_workspace(web: Web) -> None:
    listing = web.ann.get("/api/workspaces").json()
    kinds = {(w["kind"], w["owner"]) for w in listing["workspaces"]}
    assert kinds == {("personal", "ann"), ("group", "G1")}
    group = next(w for w in listing["workspaces"] if w["kind"] == "group")
    assert listing["default_id"] == group["id"]
    empty = web.ann.get(f"/api/workspaces/{group['id']}").json()
    assert (empty["revision"], empty["program"], empty["points"]) == (0, "", "")


def test_autosave_then_reload_returns_what_was_typed(web: Web) -> None:
    ws = _default(web)
    saved = web.ann.put(
        f"/api/workspaces/{ws}", json={"base": 0, "program": PROGRAM, "points": POINTS}
    )
    assert saved.status_code == 200
    assert saved.json()["revision"]["number"] == 1 and saved.json()["created"]
    again = web.ann.put(
        f"/api/workspaces/{ws}", json={"base": 1, "program": PROGRAM, "points": POINTS}
    )
    assert again.json()["created"] is False  # same content: no new revision
    # the group partner sees it
    loaded = web.bob.get(f"/api/workspaces/{ws}").json()
    assert (loaded["revision"], loaded["program"], loaded["points"]) == (1, PROGRAM, POINTS)


def test_a_save_on_an_older_revision_merges_with_what_was_saved_since(web: Web) -> None:
    """Issue 26: bob's save on revision 1 no longer drops ann's line (nor asks anyone to
    choose): both lines are in the revision it makes."""
    ws = _default(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\n", "points": ""})
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 1, "program": "MOV P1\nA\n", "points": ""})
    stale = web.bob.put(
        f"/api/workspaces/{ws}", json={"base": 1, "program": "B\nMOV P1\n", "points": ""}
    )
    assert stale.status_code == 200
    assert stale.json()["revision"]["number"] == 3
    assert stale.json()["revision"]["program"] == "B\nMOV P1\nA\n"
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "B\nMOV P1\nA\n"


def test_a_save_on_a_revision_not_kept_returns_the_current_one(web: Web) -> None:
    ws = _default(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "A\n", "points": ""})
    stale = web.bob.put(f"/api/workspaces/{ws}", json={"base": 7, "program": "B\n", "points": ""})
    error = assert_error(stale, 409, "save-conflict")
    assert error["detail"]["base"] == 7
    assert error["detail"]["current"]["number"] == 1
    assert error["detail"]["current"]["program"] == "A\n"
    assert error["detail"]["current"]["author"] == "ann"


def test_revisions_and_restore(web: Web) -> None:
    ws = _default(web)
    for base, text in enumerate(["one\n", "two\n", "three\n"]):
        web.ann.put(f"/api/workspaces/{ws}", json={"base": base, "program": text, "points": ""})
    history = web.ann.get(f"/api/workspaces/{ws}/revisions", params={"limit": 2}).json()
    assert [r["number"] for r in history["revisions"]] == [3, 2]
    assert history["next_before"] == 2
    older = web.ann.get(
        f"/api/workspaces/{ws}/revisions", params={"before": history["next_before"]}
    ).json()
    assert [r["number"] for r in older["revisions"]] == [1] and older["next_before"] is None
    assert web.ann.get(f"/api/workspaces/{ws}/revisions/1").json()["program"] == "one\n"
    restored = web.ann.post(f"/api/workspaces/{ws}/revisions/1/restore", json={"base": 3})
    assert restored.json()["revision"]["number"] == 4
    assert restored.json()["revision"]["restored_from"] == 1
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "one\n"
    assert_error(web.ann.get(f"/api/workspaces/{ws}/revisions/99"), 404, "not-found")
    # Restoring 2 ("two") from revision 3 ("three") while 4 ("one") is current: both kept.
    stale = web.ann.post(f"/api/workspaces/{ws}/revisions/2/restore", json={"base": 3})
    assert stale.json()["revision"]["program"] == "one\ntwo\n"


def test_numbers_beyond_the_database_are_refused_not_crashed(web: Web) -> None:
    """schemathesis found a 31-digit revision number overflowing SQLite's integer (a 500)."""
    ws = _default(web)
    huge = 9855871688309933529604898684928
    assert_error(web.ann.get(f"/api/workspaces/{ws}/revisions/{huge}"), 422)
    restore = web.ann.post(f"/api/workspaces/{ws}/revisions/{huge}/restore", json={"base": 0})
    assert_error(restore, 422)
    assert_error(web.ann.get(f"/api/workspaces/{huge}"), 422)
    assert_error(web.ann.get(f"/api/workspaces/{ws}/revisions/-{huge}"), 422)


def test_other_students_workspace_is_forbidden(web: Web) -> None:
    ws = _default(web, "ann")
    assert_error(web.cat.get(f"/api/workspaces/{ws}"), 403, "forbidden")
    assert_error(
        web.cat.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "", "points": ""}),
        403,
    )
    assert_error(web.cat.get("/api/workspaces/999999"), 404, "not-found")
    assert web.ivy.get(f"/api/workspaces/{ws}").status_code == 200  # staff see all


def test_import_program_and_points(web: Web) -> None:
    ws = _default(web)
    mb4 = b"10 SERVO ON\r\n20 MOV P1\r\n30 GOTO 20\r\n"
    response = web.ann.post(
        f"/api/workspaces/{ws}/import", files={"file": ("pick.MB4", mb4)}, data={"base": "0"}
    )
    assert response.status_code == 200, response.text
    program = response.json()["revision"]["program"]
    assert "10 SERVO" not in program and "SERVO ON" in program
    pos = web.ann.post(
        f"/api/workspaces/{ws}/import",
        files={"file": ("points.pos", POINTS.encode())},
        data={"base": "1"},
    )
    assert pos.json()["revision"]["points"] == POINTS
    assert pos.json()["revision"]["program"] == program  # the other half stays
    assert pos.json()["revision"]["reason"] == "import"


def test_import_wrong_extension_refused_clearly(web: Web) -> None:
    ws = _default(web)
    response = web.ann.post(
        f"/api/workspaces/{ws}/import", files={"file": ("notes.txt", b"MOV P1")}, data={"base": "0"}
    )
    error = assert_error(response, 422, "wrong-extension")
    assert "notes.txt" in error["message"] and ".MB4" in error["message"]
    assert error["where"] == {"file": "notes.txt"}
    broken = web.ann.post(
        f"/api/workspaces/{ws}/import",
        files={"file": ("bad.pos", b"DEF POS P1=(1,2\n")},
        data={"base": "0"},
    )
    error = assert_error(broken, 422, "file-not-convertible")
    assert error["where"]["line"] == 1 and error["detail"]["diagnostics"]
    missing = web.ann.post(f"/api/workspaces/{ws}/import", data={"base": "0"})
    assert_error(missing, 422, "invalid-request")
    assert web.ann.get(f"/api/workspaces/{ws}").json()["revision"] == 0  # nothing saved


def test_export_numbered_program_and_points(web: Web) -> None:
    ws = _default(web)
    web.ann.put(
        f"/api/workspaces/{ws}",
        json={"base": 0, "program": "SERVO ON\n*LOOP\nMOV P1\nGOTO *LOOP\n", "points": POINTS},
    )
    program = web.ann.get(f"/api/workspaces/{ws}/export/program")
    assert program.status_code == 200
    assert program.headers["content-disposition"] == 'attachment; filename="G1.MB4"'
    assert program.text.startswith("10 SERVO ON\r\n20 *LOOP\r\n")
    points = web.ann.get(f"/api/workspaces/{ws}/export/points")
    assert points.headers["content-disposition"].endswith('.POS"')
    assert "DEF POS P1=(300.00" in points.text
    assert_error(web.ann.get(f"/api/workspaces/{ws}/export/txt"), 422, "invalid-request")


def test_nothing_lost_across_a_server_restart(web: Web, tmp_path: Path) -> None:
    ws = _default(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": PROGRAM, "points": POINTS})
    token = web.ann.token
    web.client.__exit__(None, None, None)  # the server goes away
    web.store.close()
    with make_store(tmp_path / "data") as store:
        settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
        with TestClient(create_app(settings, store=store)) as client:
            again = client.get(
                f"/api/workspaces/{ws}", headers={"cookie": f"melfa_session={token}"}
            )
            assert again.status_code == 200
            assert (again.json()["program"], again.json()["points"]) == (PROGRAM, POINTS)
