"""The instructor's desk over REST: accounts managed by staff (instructors their students,
admins everyone: one rule, `Role.may_manage`), a class list imported from the CSV that
`melfa users import` reads, and the simulation gate switched live; each change audited."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient

from melfa.vocab.desk import DESK_WORDS
from melfa.vocab.refusals import Refusal
from melfa.web import WebSettings, create_app
from tests.web.conftest import Web, assert_error, fast_service, make_store

HELD_TEXT = " ".join(Refusal.HELD.words(who="ivy"))
"""What every door says while ivy holds the robot (one home: `melfa.vocab.refusals`)."""

CLASS_LIST = "username,name,group\ndora,Dora Diaz,G3\neli,Eli Ek,G3\nann,Ann A,G1\n"
PROGRAM = "MOV P1\nEND"
POINTS = "P1=(400.00,0.00,500.00,180.00,0.00,180.00)(7,0)"


def _actions(web: Web, actor: str) -> list[tuple[str, dict[str, object]]]:
    page = web.store.audit.query(actor=actor, limit=50)
    return [(e.action, e.details) for e in reversed(page.entries) if e.action != "session.sign-in"]


def test_an_instructor_manages_students_only(web: Web) -> None:
    ivy = web.ivy
    names = [u["username"] for u in ivy.get("/api/users").json()["users"]]
    assert names == ["ann", "bob", "cat"]  # no admin, no instructor
    refused = assert_error(
        ivy.post("/api/users", json={"username": "zed", "role": "instructor"}), 403
    )
    assert refused["message"] == DESK_WORDS["not-yours"].format(
        role="instructor", other="instructor"
    )
    assert_error(ivy.put("/api/users/admin/password", json={}), 403, "forbidden")
    assert_error(ivy.delete("/api/users/admin"), 403, "forbidden")
    created = ivy.post("/api/users", json={"username": "gus", "group": "G2"})
    assert created.status_code == 201, created.text
    new = ivy.put("/api/users/bob/password", json={})
    password = new.json()["password"]
    assert password and len(password) >= 12
    signed_in = web.client.post("/api/session", json={"username": "bob", "password": password})
    assert signed_in.status_code == 200
    web.client.cookies.clear()
    assert ivy.delete("/api/users/gus").json() == {"ok": True}
    assert [a for a, _ in _actions(web, "ivy")] == [
        "account.add",
        "account.password",
        "account.remove",
    ]
    assert _actions(web, "ivy")[1][1] == {"who": "bob"}


def test_a_class_list_is_imported_all_or_nothing(web: Web) -> None:
    ivy = web.ivy
    bad = "username,name,group\ndora,Dora,G3\nx,Bad,G3\n"
    error = assert_error(ivy.post("/api/users/import", json={"csv": bad}), 422, "invalid-value")
    assert error["detail"]["problems"][0]["line"] == 3
    assert web.store.accounts.find_user("dora") is None  # nothing half-imported
    staff = "username,name,group,role\nzoe,Zoe,G3,instructor\n"
    assert_error(ivy.post("/api/users/import", json={"csv": staff}), 403, "forbidden")
    report = ivy.post("/api/users/import", json={"csv": CLASS_LIST}).json()
    assert report["created"] == ["dora", "eli"] and report["skipped"] == ["ann"]
    assert sorted(report["passwords"]) == ["dora", "eli"]
    dora = web.client.post(
        "/api/session", json={"username": "dora", "password": report["passwords"]["dora"]}
    )
    assert dora.status_code == 200 and dora.json()["user"]["group"] == "G3"
    web.client.cookies.clear()
    assert _actions(web, "ivy") == [("account.import", {"count": 2})]


def test_the_gate_is_switched_live_and_every_load_obeys(web: Web) -> None:
    ann, ivy = web.ann, web.ivy
    assert_error(ann.put("/api/desk/gate", json={"require_simulation": True}), 403)
    default = {
        "source": "default",  # nobody set it, and the server started without the option
        "by": None,
        "at": None,
        "command_line": None,
        "until_restart": False,
        "cut_from": [],
    }
    assert ivy.get("/api/desk").json() == {
        "require_simulation": False,
        "require_simulation_from": default,
        "held_by": None,
        "lab_networks": [],  # anywhere, unless told
        "lab_networks_from": default,
        "your_address": None,  # the test client has no address
    }
    on = ivy.put("/api/desk/gate", json={"require_simulation": True})
    assert on.json()["require_simulation"] is True
    origin = on.json()["require_simulation_from"]
    assert (origin["source"], origin["by"], origin["until_restart"]) == ("desk", "ivy", False)
    assert web.store.robot_settings.load("lab")["require_simulation"].value is True  # saved
    body = {"program": PROGRAM, "points": POINTS}
    assert_error(ann.post("/api/robot/project", json=body), 409, "simulation-required")
    assert ann.get("/api/preflight").json()["require_simulation"] is True
    ivy.put("/api/desk/gate", json={"require_simulation": False})
    loaded = ann.post("/api/robot/project", json=body)
    assert loaded.status_code == 200, loaded.text
    assert _actions(web, "ivy") == [("gate.set", {"state": "on"}), ("gate.set", {"state": "off"})]


def _ws_ask(web: Web, user: str, message: dict[str, Any]) -> dict[str, Any]:
    with getattr(web, user).ws() as ws:
        ws.send_text(json.dumps({**message, "id": 7}))
        while True:
            reply: dict[str, Any] = json.loads(ws.receive_text())
            if reply.get("id") == 7:
                return reply


def test_an_instructors_stop_holds_until_released(web: Web) -> None:
    ann, ivy = web.ann, web.ivy
    body = {"program": PROGRAM, "points": POINTS}
    assert ann.post("/api/lease").status_code == 200
    assert_error(ann.post("/api/desk/hold"), 403, "forbidden")
    held = ivy.post("/api/desk/hold")
    assert (held.json()["require_simulation"], held.json()["held_by"]) == (False, "ivy")
    error = assert_error(ann.post("/api/robot/project", json=body), 423, "held")
    assert error["message"] == HELD_TEXT  # the student is told who stopped it
    assert_error(ann.post("/api/robot/run"), 423, "held")
    # The staff side resets an alarm without taking over (ann keeps the lease).
    assert ivy.post("/api/robot/reset-alarm").json() == {"ok": True}
    assert ann.get("/api/lease").json()["holder"]["user"] == "ann"
    assert_error(web.bob.post("/api/robot/reset-alarm"), 423, "held")
    jog = _ws_ask(web, "ann", {"type": "jog_start", "frame": "joint", "axis": 1, "direction": 1})
    assert (jog["error"]["code"], jog["error"]["message"]) == ("held", HELD_TEXT)
    released = ivy.delete("/api/desk/hold")
    assert released.json()["held_by"] is None
    loaded = ann.post("/api/robot/project", json=body)
    assert loaded.status_code == 200, loaded.text
    actions = [a for a, _ in _actions(web, "ivy")]
    assert [a for a in actions if a.startswith("desk.")] == ["desk.hold", "desk.release"]
    assert "robot.stop" in actions


def test_a_sign_in_is_audited_and_a_wrong_one_is_not(web: Web) -> None:
    wrong = web.client.post("/api/session", json={"username": "ann", "password": "not-it-123"})
    assert wrong.status_code == 401
    web.ann.get("/api/session")
    entries = web.store.audit.query(action="session.sign-in").entries
    assert [(e.actor, e.role, e.result) for e in entries] == [("ann", "student", "ok")]


def test_the_desks_gate_survives_a_new_app_on_the_same_database(tmp_path: Path) -> None:
    """The app factory twice on one SQLite file (a restart, in process; the real `melfa
    serve` restarted is tests/web/test_desk_restart.py)."""
    settings = WebSettings(data_dir=tmp_path / "data", service_config=fast_service())
    body = {"program": PROGRAM, "points": POINTS}
    with make_store(tmp_path / "data") as store:
        app = create_app(settings, store=store)
        with TestClient(app) as client:
            web = Web(client, store, app)
            assert web.ivy.put("/api/desk/gate", json={"require_simulation": True}).is_success
    with make_store(tmp_path / "data") as store:
        app = create_app(settings, store=store)
        with TestClient(app) as client:
            web = Web(client, store, app)
            desk = web.ivy.get("/api/desk").json()
            assert desk["require_simulation"] is True
            assert desk["require_simulation_from"]["by"] == "ivy"
            assert_error(web.ann.post("/api/robot/project", json=body), 409, "simulation-required")
            assert_error(web.ann.post("/api/queue", json=body), 409, "simulation-required")
