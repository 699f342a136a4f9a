"""Staff open a student's workspace read-only (issue 26, the instructor's desk): the server
refuses every write of theirs (save, restore, import, rename) until this sign-in chose
*Edit as instructor*, which the audit log records, and again once they go back to
reading. Members of the workspace are never asked."""

from __future__ import annotations

from typing import Any

from melfa.vocab.desk import DeskAction
from tests.web.conftest import Web, assert_error


def _anns(web: Web) -> int:
    return int(web.ann.get("/api/workspaces").json()["default_id"])


def _save(web: Web, ws: int, program: str) -> Any:
    base = web.ann.get(f"/api/workspaces/{ws}").json()["revision"]
    return web.ivy.put(
        f"/api/workspaces/{ws}", json={"base": base, "program": program, "points": ""}
    )


def test_staff_write_only_after_asking_to_edit_and_it_is_audited(web: Web) -> None:
    ws = _anns(web)
    saved = web.ann.put(
        f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\n", "points": ""}
    )
    assert saved.status_code == 200
    assert web.ivy.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\n"  # reads

    error = assert_error(_save(web, ws, "' the instructor's typo\n"), 403, "read-only")
    assert "G1's work" in error["message"] and "Edit as instructor" in error["message"]
    assert_error(web.ivy.post(f"/api/workspaces/{ws}/revisions/1/restore", json={}), 403)
    assert_error(web.ivy.patch(f"/api/workspaces/{ws}", json={"name": "mine now"}), 403)
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\n"

    granted = web.ivy.put(f"/api/workspaces/{ws}/staff-edit")
    assert granted.json() == {"writable": True, "visiting": True}
    assert _save(web, ws, "MOV P1\nMOV P2\n").status_code == 200
    assert web.ann.get(f"/api/workspaces/{ws}").json()["program"] == "MOV P1\nMOV P2\n"

    back = web.ivy.delete(f"/api/workspaces/{ws}/staff-edit")
    assert back.json() == {"writable": False, "visiting": True}
    assert_error(_save(web, ws, "END\n"), 403, "read-only")

    entries = web.ivy.get("/api/audit?actor=ivy").json()["entries"]
    actions = [e["action"] for e in entries if e["action"].startswith("workspace.")]
    assert actions == [DeskAction.READ_ONLY.value, DeskAction.EDIT_AS_STAFF.value]
    assert entries[0]["details"]["who"] == "G1"


def test_the_grant_is_one_sign_in_s_and_members_never_ask(web: Web) -> None:
    ws = _anns(web)
    web.ann.put(f"/api/workspaces/{ws}", json={"base": 0, "program": "MOV P1\n", "points": ""})
    assert web.ivy.put(f"/api/workspaces/{ws}/staff-edit").status_code == 200
    again = web.login("ivy")  # another sign-in of the same instructor: read-only there
    assert_error(
        again.put(f"/api/workspaces/{ws}", json={"base": 1, "program": "", "points": ""}), 403
    )
    mine = web.ann.put(f"/api/workspaces/{ws}/staff-edit").json()
    assert mine == {"writable": True, "visiting": False}
    assert (
        web.ann.put(
            f"/api/workspaces/{ws}", json={"base": 1, "program": "", "points": ""}
        ).status_code
        == 200
    )
