"""The browser's RV-6S model is melfa.kin's: the 3D view imports /model/rv6s.js, ROS tools
can fetch /model/rv6s.urdf; the controller's facts the IDE shows (axis names, hand numbers,
the override range) are melfa.protocol's, from /model/controller.js."""

from __future__ import annotations

import json
import re

from melfa.kin import DH, HOME, JOINT_LIMITS
from melfa.protocol import HANDS, JOINT_NAMES, OVERRIDE_PERCENT, POSE_NAMES
from melfa.web.routes.pages import STATIC
from tests.web.conftest import Web


def test_the_3d_view_model_is_melfa_kin(web: Web) -> None:
    reply = web.client.get("/model/rv6s.js")
    assert reply.status_code == 200 and "javascript" in reply.headers["content-type"]
    values = dict(re.findall(r"export const (\w+) = (.*);", reply.text))
    rows = json.loads(values["DH"])
    assert [(r["a"], r["d"], r["alpha"], r["offset"]) for r in rows] == [
        (r.a, r.d, r.alpha, r.offset) for r in DH
    ]
    assert json.loads(values["HOME"]) == list(HOME)
    assert json.loads(values["JOINT_LIMITS"]) == [list(j) for j in JOINT_LIMITS]
    # the view has no table of its own
    assert "a: 85" not in (STATIC / "js" / "view3d.js").read_text(encoding="utf-8")


def test_the_urdf_is_served(web: Web) -> None:
    reply = web.client.get("/model/rv6s.urdf")
    assert reply.status_code == 200 and '<joint name="joint_6"' in reply.text


def test_the_controllers_facts_are_melfa_protocols(web: Web) -> None:
    reply = web.client.get("/model/controller.js")
    assert reply.status_code == 200 and "javascript" in reply.headers["content-type"]
    found = re.findall(r"export const (\w+) = Object\.freeze\((.*)\);", reply.text)
    values = {name: json.loads(value) for name, value in found}
    assert values == {
        "JOINT_NAMES": list(JOINT_NAMES),
        "POSE_NAMES": list(POSE_NAMES),
        "HANDS": {"min": HANDS.start, "max": HANDS[-1]},
        "OVERRIDE_PERCENT": {"min": OVERRIDE_PERCENT.start, "max": OVERRIDE_PERCENT[-1]},
    }
    # the scripts that show them import the module (their own copies: test_one_home.py)
    for script in ("main.js", "jog.js", "points.js"):
        text = (STATIC / "js" / script).read_text(encoding="utf-8")
        assert 'from "/model/controller.js"' in text, script
