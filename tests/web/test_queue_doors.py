"""The lab robot's queue through a real uvicorn (in this process, so the test owns the
queue's clock: a `FakeClock` it moves on itself, never a sleep): entering goes through the
policy (an unsimulated text cannot), while the queue is active the arm is given only by
the queue at every door — REST, the WebSocket, rosbridge, the thesis's messages in both
modes — STOP works for everyone from every door, the head's claim gives them the lease,
a turn ends on time and hands over, and the audit log has every transition. Third-party
clients unmodified: httpx, websockets, roslibpy."""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import roslibpy
from websockets.sync.client import connect

from melfa.service.clock import FakeClock
from melfa.service.queue import QueueSettings
from melfa.vocab.refusals import Refusal
from melfa.web import WebSettings
from tests.waiting import wait_until
from tests.web.conftest import fast_service, make_store
from tests.web.live_server import Live, live_server

pytestmark = pytest.mark.timeout(240)

POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
PROGRAM = "' queued\nSERVO ON\nMOV P1\nEND\n"
QUEUE_TEXT = " ".join(Refusal.QUEUE_ACTIVE.words())
"""What every door says to someone whose turn it is not (one home: `melfa.vocab.refusals`)."""
SETTINGS = QueueSettings(claim_s=60, turn_s=240, warn_s=30, grace_s=120)


class Person:
    """A signed-in user: REST with their cookie, a WebSocket kept open, a token for ROS."""

    def __init__(self, live: Live, user: str) -> None:
        self.live = live
        self.user = user
        self.token, self.csrf = live.login(user)
        self.ws: Any = None
        self.messages: list[dict[str, Any]] = []
        self._lock = threading.Lock()

    def rest(self, method: str, path: str, body: Any = None) -> Any:
        headers = {"Cookie": f"melfa_session={self.token}", "X-CSRF-Token": self.csrf}
        with self.live.client() as c:
            return c.request(method, path, json=body, headers=headers)

    def open(self) -> None:
        """A socket kept open (the IDE's), its messages read on a thread."""
        self.ws = connect(
            f"ws://127.0.0.1:{self.live.port}/api/ws",
            additional_headers={"Cookie": f"melfa_session={self.token}"},
            legacy=True,
        )
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        try:
            for text in self.ws:
                with self._lock:
                    self.messages.append(json.loads(text))
        except Exception as exc:
            with self._lock:
                self.messages.append({"type": "gone", "why": repr(exc)})

    def kinds(self) -> list[str]:
        with self._lock:
            return [m["type"] for m in self.messages if m["type"] != "state"]

    def queues(self) -> list[dict[str, Any]]:
        with self._lock:
            return [m for m in self.messages if m["type"] == "queue"]

    def ask(self, message: dict[str, Any]) -> dict[str, Any]:
        """One message on a socket of its own, and its answer."""
        headers = {"Cookie": f"melfa_session={self.token}"}
        with connect(f"ws://127.0.0.1:{self.live.port}/api/ws", additional_headers=headers) as ws:
            ws.send(json.dumps({**message, "id": 7}))
            while True:
                reply = json.loads(ws.recv(timeout=30))
                if reply.get("id") == 7:
                    return dict(reply)

    def access_token(self) -> str:
        made = self.rest("POST", "/api/tokens", {"label": "doors"})
        assert made.status_code == 201, made.text
        return str(made.json()["token"])


@pytest.fixture
def lab(tmp_path: Path) -> Iterator[tuple[Live, FakeClock]]:
    store = make_store(tmp_path / "data")
    clock = FakeClock(start=time.time())
    settings = WebSettings(
        data_dir=tmp_path / "data",
        service_config=fast_service(),
        require_simulation=True,
        queue=SETTINGS,
    )
    with live_server(store, settings, queue_clock=clock) as server:
        yield server, clock
    store.close()


def thesis_says(live: Live, token: str, mode: str, message: str) -> str:
    """The thesis's control ``message`` over rosbridge in ``mode``: the first
    ``/execute_error`` it brings."""
    ros = roslibpy.Ros(host=f"ws://127.0.0.1:{live.port}/rosbridge?token={token}&mode={mode}")
    ros.run(timeout=20)
    try:
        said: list[str] = []
        errors = roslibpy.Topic(ros, "/execute_error", "std_msgs/String")
        errors.subscribe(lambda m: said.append(m["data"]))
        topic = roslibpy.Topic(ros, "/execute_instruction", "std_msgs/String")
        topic.publish(roslibpy.Message({"data": message}))
        wait_until(lambda: said, what=f"the thesis's error ({mode})")
        return said[0]
    finally:
        ros.close()


def advance(clock: FakeClock, seconds: float) -> None:
    clock.advance_to(clock.now() + seconds)


def test_only_the_queue_gives_the_arm_at_every_door(lab: tuple[Live, FakeClock]) -> None:
    live, clock = lab
    ann, bob, cat, ivy = (Person(live, u) for u in ("ann", "bob", "cat", "ivy"))
    for person in (ann, bob, ivy):
        person.open()
    bob_token = bob.access_token()

    # An unsimulated text cannot enter; the same text after pre-flight can.
    body = {"program": PROGRAM, "points": POINTS}
    refused = ann.rest("POST", "/api/queue", body)
    assert (refused.status_code, refused.json()["error"]["code"]) == (409, "simulation-required")
    broken = cat.rest("POST", "/api/queue", {"program": "MOV P1\nGOTO 99\n", "points": POINTS})
    assert broken.json()["error"]["code"] == "program-has-errors"
    for person in (ann, bob):
        ran = person.rest("POST", "/api/preflight", body)
        assert ran.json()["passed"] is True, ran.text
        joined = person.rest("POST", "/api/queue", body)
        assert joined.status_code == 200, joined.text
    queue = joined.json()
    assert [(e["user"], e["position"], e["state"]) for e in queue["entries"]] == [
        ("ann", 1, "offered"),
        ("bob", 2, "waiting"),
    ]
    assert queue["entries"][0]["cycle_s"] is not None  # from pre-flight: the estimates use it
    assert queue["entries"][1]["estimate"] > queue["entries"][0]["estimate"]
    # Everyone sees it live, whoever they are
    wait_until(
        lambda: any(len(m["entries"]) == 2 for m in ivy.queues()),
        what=lambda: f"ivy's queue: {ivy.kinds()} {ivy.messages[-1:]}",
    )

    # The arm is free but the queue gives it: nobody takes it, from any door
    taken = bob.rest("POST", "/api/lease")
    assert (taken.status_code, taken.json()["error"]["code"]) == (423, "queue-active")
    assert taken.json()["error"]["message"] == QUEUE_TEXT
    servo = bob.rest("POST", "/api/robot/servo", {"on": True})
    assert (servo.status_code, servo.json()["error"]["message"]) == (423, QUEUE_TEXT)
    jog = bob.ask({"type": "jog_start", "frame": "joint", "axis": 1, "direction": 1})
    assert jog["error"]["code"] == "queue-active"
    ros = roslibpy.Ros(host=f"ws://127.0.0.1:{live.port}/rosbridge?token={bob_token}")
    ros.run(timeout=20)
    try:
        service = roslibpy.Service(ros, "/melfa/servo", "std_srvs/SetBool")
        reply = service.call(roslibpy.ServiceRequest({"data": True}), timeout=60)
        assert reply == {"success": False, "message": QUEUE_TEXT}
    finally:
        ros.close()
    for mode in ("melfa", "thesis"):
        assert thesis_says(live, bob_token, mode, "---MOV TOOL +X---") == QUEUE_TEXT
    assert live.context.service.lease_holder is None

    # STOP works for everyone, from every door
    assert bob.rest("POST", "/api/robot/stop").status_code == 200
    assert bob.ask({"type": "stop"})["type"] == "ack"

    # The head claims: the lease is hers, without anyone else's click
    claimed = ann.rest("POST", "/api/queue/claim", {"start": False})
    assert claimed.status_code == 200, claimed.text
    assert claimed.json()["turn"]["user"] == "ann"
    assert ann.rest("GET", "/api/lease").json()["you"] is True
    assert bob.rest("POST", "/api/queue/claim", {}).json()["error"]["code"] == "not-your-turn"
    assert ann.rest("POST", "/api/robot/servo", {"on": True}).status_code == 200
    servo = bob.rest("POST", "/api/robot/servo", {"on": False})
    assert (servo.status_code, servo.json()["error"]["code"]) == (423, "queue-active")

    # The turn ends on time and hands over: bob is offered the arm
    advance(clock, 239)
    wait_until(lambda: any(m["turn"] and m["turn"]["warned"] for m in ann.queues()))
    assert ann.rest("GET", "/api/lease").json()["you"] is True
    advance(clock, 2)
    now = wait_until(
        lambda: (q := bob.rest("GET", "/api/queue").json())["turn"] is None and q,
        what="the turn to end",
    )
    assert now["entries"][0] == {**now["entries"][0], "user": "bob", "state": "offered"}
    assert ann.rest("GET", "/api/lease").json()["holder"] is None
    steps = [s["kind"] for m in bob.queues() for s in m["steps"]]
    assert steps.count("joined") == 2 and "claimed" in steps and "ended" in steps
    live.store.db.flush()
    actions = [e.action for e in live.store.audit.query(limit=100).entries]
    for action in ("queue.joined", "queue.offered", "queue.claimed", "queue.warned", "queue.ended"):
        assert action in actions


def test_instructor_controls_and_a_stale_entry(lab: tuple[Live, FakeClock]) -> None:
    live, clock = lab
    ann, bob, cat, ivy = (Person(live, u) for u in ("ann", "bob", "cat", "ivy"))
    for person in (ann, bob, cat):
        person.open()
    body = {"program": PROGRAM, "points": POINTS}
    for person in (ann, bob, cat):
        person.rest("POST", "/api/preflight", body)
        assert person.rest("POST", "/api/queue", body).status_code == 200
    assert ann.rest("POST", "/api/queue/move", {"user": "cat", "position": 1}).status_code == 403
    moved = ivy.rest("POST", "/api/queue/move", {"user": "cat", "position": 1}).json()
    assert [e["user"] for e in moved["entries"]] == ["cat", "ann", "bob"]
    skipped = ivy.rest("POST", "/api/queue/skip", {"user": "ann"}).json()
    assert [e["user"] for e in skipped["entries"]] == ["cat", "bob"]
    paused = ivy.rest("POST", "/api/queue/pause").json()
    assert paused["paused"] and all(e["state"] == "waiting" for e in paused["entries"])
    advance(clock, 600)  # nothing is offered while paused, nobody misses a claim
    assert ivy.rest("GET", "/api/queue").json()["entries"][0]["missed"] == 0
    resumed = ivy.rest("POST", "/api/queue/resume").json()
    assert resumed["entries"][0]["state"] == "offered"
    assert cat.rest("POST", "/api/queue/claim", {"start": False}).status_code == 200
    extended = ivy.rest("POST", "/api/queue/extend", {"seconds": 60}).json()
    assert extended["turn"]["left_s"] == pytest.approx(300, abs=1)
    took = ivy.rest("POST", "/api/queue/take").json()
    assert took["paused"] and took["turn"]["held"]
    assert ivy.rest("GET", "/api/lease").json()["you"] is True
    back = ivy.rest("POST", "/api/queue/resume").json()
    assert not back["turn"]["held"] and cat.rest("GET", "/api/lease").json()["you"] is True

    # bob changes his workspace's program after queueing it from there: his entry is stale
    ws = bob.rest("GET", "/api/workspaces").json()["workspaces"][0]  # his own
    state = bob.rest("GET", f"/api/workspaces/{ws['id']}").json()
    saved = bob.rest(
        "PUT",
        f"/api/workspaces/{ws['id']}",
        {"program": PROGRAM, "points": POINTS, "base": state["revision"]},
    )
    assert saved.status_code == 200, saved.text
    assert bob.rest("POST", "/api/preflight", {"workspace_id": ws["id"]}).json()[
        "passed"
    ]  # the workspace's text
    from_ws = bob.rest("POST", "/api/queue", {"workspace_id": ws["id"]})
    assert from_ws.status_code == 200, from_ws.text
    assert not bob.rest("GET", "/api/queue").json()["entries"][0]["stale"]
    bob.rest(
        "PUT",
        f"/api/workspaces/{ws['id']}",
        {
            "program": PROGRAM + "' more\n",
            "points": POINTS,
            "base": saved.json()["revision"]["number"],
        },
    )
    assert bob.rest("GET", "/api/queue").json()["entries"][0]["stale"] is True
