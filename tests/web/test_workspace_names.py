"""Named workspaces through the API: several per user, created (from an opened file too),
renamed, archived, listed with name, kind, owner and whether shared; staff rules as for
the rest of the workspace API."""

from __future__ import annotations

from tests.web.conftest import Web, assert_error

PROGRAM = "SERVO ON\nMOV P1\nEND\n"
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def _listing(web: Web, who: str = "ann", **params: str) -> dict[str, dict[str, object]]:
    out = getattr(web, who).get("/api/workspaces", params=params).json()
    return {str(w["name"]): w for w in out["workspaces"]}


def test_listing_names_each_workspace_and_says_which_is_shared(web: Web) -> None:
    listing = _listing(web)
    assert set(listing) == {"My programs", "G1"}
    mine, group = listing["My programs"], listing["G1"]
    assert (mine["kind"], mine["owner"], mine["shared"], mine["archived"]) == (
        "personal",
        "ann",
        False,
        False,
    )
    assert (group["kind"], group["owner"], group["shared"]) == ("group", "G1", True)


def test_open_beside_creates_a_workspace_holding_the_file(web: Web) -> None:
    default = web.ann.get("/api/workspaces").json()["default_id"]
    web.ann.put(f"/api/workspaces/{default}", json={"base": 0, "program": "OLD\n", "points": ""})
    made = web.ann.post(
        "/api/workspaces",
        json={"name": "pyramid", "program": PROGRAM, "points": POINTS, "from_file": "PYR.MB4"},
    )
    assert made.status_code == 201, made.text
    body = made.json()
    assert (body["name"], body["kind"], body["owner"], body["shared"]) == (
        "pyramid",
        "personal",
        "ann",
        False,
    )
    assert (body["revision"], body["program"], body["points"]) == (1, PROGRAM, POINTS)
    history = web.ann.get(f"/api/workspaces/{body['id']}/revisions").json()["revisions"]
    assert [r["reason"] for r in history] == ["import"]
    assert web.ann.get(f"/api/workspaces/{default}").json()["program"] == "OLD\n"
    assert set(_listing(web)) == {"My programs", "pyramid", "G1"}
    # Nobody else's list shows it, and another student cannot open it.
    assert "pyramid" not in _listing(web, "bob")
    assert_error(web.bob.get(f"/api/workspaces/{body['id']}"), 403, "forbidden")


def test_names_are_checked_and_refusals_say_why(web: Web) -> None:
    assert web.ann.post("/api/workspaces", json={"name": "Lab 1"}).status_code == 201
    taken = assert_error(
        web.ann.post("/api/workspaces", json={"name": " lab 1 "}), 409, "already-exists"
    )
    assert "already have a workspace called “Lab 1”" in taken["message"]
    empty = assert_error(web.ann.post("/api/workspaces", json={"name": "  "}), 422)
    assert "needs a name" in empty["message"]
    assert "SELECT" not in empty["message"] and "Traceback" not in empty["message"]
    long = assert_error(web.ann.post("/api/workspaces", json={"name": "x" * 61}), 422)
    assert "at most 60" in long["message"]
    assert web.bob.post("/api/workspaces", json={"name": "Lab 1"}).status_code == 201


def test_rename_and_archive(web: Web) -> None:
    made = web.ann.post("/api/workspaces", json={"name": "draft", "program": PROGRAM}).json()
    renamed = web.ann.patch(f"/api/workspaces/{made['id']}", json={"name": "Pyramid"})
    assert renamed.status_code == 200 and renamed.json()["name"] == "Pyramid"
    assert_error(
        web.ann.patch(f"/api/workspaces/{made['id']}", json={"name": "my programs"}),
        409,
        "already-exists",
    )
    assert_error(web.bob.patch(f"/api/workspaces/{made['id']}", json={"name": "mine"}), 403)
    hidden = web.ann.patch(f"/api/workspaces/{made['id']}", json={"archived": True}).json()
    assert hidden["archived"] is True
    assert "Pyramid" not in _listing(web)
    assert _listing(web, archived="true")["Pyramid"]["archived"] is True
    assert web.ann.get(f"/api/workspaces/{made['id']}").json()["program"] == PROGRAM
    default = web.ann.get("/api/workspaces").json()["workspaces"][0]["id"]
    assert_error(web.ann.patch(f"/api/workspaces/{default}", json={"archived": True}), 422)
    back = web.ann.patch(f"/api/workspaces/{made['id']}", json={"archived": False}).json()
    assert back["archived"] is False and "Pyramid" in _listing(web)


def test_group_workspace_renamed_by_a_member_stays_shared(web: Web) -> None:
    group = _listing(web)["G1"]
    out = web.bob.patch(f"/api/workspaces/{group['id']}", json={"name": "Team pyramid"})
    assert out.json()["name"] == "Team pyramid" and out.json()["shared"] is True
    assert _listing(web)["Team pyramid"]["owner"] == "G1"
    assert_error(web.cat.patch(f"/api/workspaces/{group['id']}", json={"name": "x"}), 403)


def test_staff_see_and_rename_but_create_only_their_own(web: Web) -> None:
    made = web.ann.post("/api/workspaces", json={"name": "exam"}).json()
    staff = web.ivy.get("/api/workspaces").json()["workspaces"]
    assert made["id"] in {w["id"] for w in staff}
    # a student's work opens read-only for staff: a rename only after *Edit as instructor*
    rename = {"name": "exam (seen)"}
    assert_error(web.ivy.patch(f"/api/workspaces/{made['id']}", json=rename), 403, "read-only")
    assert web.ivy.put(f"/api/workspaces/{made['id']}/staff-edit").status_code == 200
    renamed = web.ivy.patch(f"/api/workspaces/{made['id']}", json=rename)
    assert renamed.status_code == 200
    own = web.ivy.post("/api/workspaces", json={"name": "exam"}).json()
    assert own["owner"] == "ivy"
