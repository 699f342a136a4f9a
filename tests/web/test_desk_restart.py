"""The desk's settings survive a restart: a real `melfa serve` (a subprocess, a traced TCP
virtual controller, rosbridge on its own port) is stopped and started again on the same
data directory, as a crash, a reboot or the technician's update would. A gate the
instructor turned on at the desk still refuses an unsimulated program at REST and
rosbridge, nothing of it reaches the controller, and the desk says who set it. Started with
``--require-simulation --lab-network``, the options are the floor: a saved "off" and a
saved "anywhere" do not lower them, and the desk says the server's options set them; a
saved list only partly inside the option's networks is cut to that part at start, and the
desk shows what holds and what was saved."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from melfa.vocab.refusals import Refusal
from tests.web.doors import POINTS, Lab, call, lab_server, program

pytestmark = [pytest.mark.timeout(300), pytest.mark.slow]

GATE_TEXT = " ".join(Refusal.SIMULATION_REQUIRED.words())
OUTSIDE = " ".join(Refusal.OUTSIDE_LAB.words())
HERE, ELSEWHERE, INSIDE = "127.0.0.0/8", "10.0.0.0/8", "10.1.0.0/16"


def desk(lab: Lab, method: str = "GET", path: str = "", body: Any = None) -> dict[str, Any]:
    reply = lab.rest("admin", method, "/api/desk" + path, body)
    assert reply.status_code == 200, reply.text
    found: dict[str, Any] = reply.json()
    return found


def test_the_desks_gate_and_networks_hold_after_a_restart(tmp_path: Path) -> None:
    data = tmp_path / "lab"
    data.mkdir()
    with lab_server(data) as lab:  # no start-up options: the defaults
        lab.add_students(["ann"])
        first = desk(lab)
        assert (first["require_simulation"], first["require_simulation_from"]["source"]) == (
            False,
            "default",
        )
        on = desk(lab, "PUT", "/gate", {"require_simulation": True})
        assert on["require_simulation_from"]["by"] == "admin"
        desk(lab, "PUT", "/lab-network", {"networks": [HERE]})

    with lab_server(data) as lab:  # restarted on the same database
        lab.sign_in("ann", "ann-password-12")
        after = desk(lab)
        assert (after["require_simulation"], after["lab_networks"]) == (True, [HERE])
        for name in ("require_simulation_from", "lab_networks_from"):
            origin = after[name]
            assert (origin["source"], origin["by"], origin["until_restart"]) == (
                "desk",
                "admin",
                False,
            ), name
        load = {"program": program("restart"), "points": POINTS}
        refused = lab.rest("ann", "POST", "/api/robot/project", load)
        assert (refused.status_code, refused.json()["error"]["message"]) == (409, GATE_TEXT)
        ros = lab.ros("ann", "melfa")
        try:
            assert call(ros, "load_project", load) == {"success": False, "message": GATE_TEXT}
        finally:
            ros.close()
        assert b"door restart" not in lab.sent()  # the controller never got it
        # The instructor lets everything go again: saved too.
        desk(lab, "PUT", "/gate", {"require_simulation": False})
        desk(lab, "PUT", "/lab-network", {"networks": []})

    with lab_server(data, "--require-simulation", "--lab-network", ELSEWHERE) as lab:
        lab.sign_in("ann", "ann-password-12")
        floor = desk(lab)
        assert (floor["require_simulation"], floor["lab_networks"]) == (True, [ELSEWHERE])
        assert floor["require_simulation_from"] == {
            "source": "command-line",
            "by": None,
            "at": None,
            "command_line": "--require-simulation",
            "until_restart": False,
            "cut_from": [],
        }
        networks = floor["lab_networks_from"]
        assert (networks["source"], networks["command_line"]) == (
            "command-line",
            f"--lab-network {ELSEWHERE}",
        )
        taken = lab.rest("ann", "POST", "/api/lease")  # from 127.0.0.1, outside 10.0.0.0/8
        assert (taken.status_code, taken.json()["error"]["message"]) == (403, OUTSIDE)
        # Switched off live under the option: the desk says a restart turns it on again.
        off = desk(lab, "PUT", "/gate", {"require_simulation": False})
        assert (off["require_simulation"], off["require_simulation_from"]["until_restart"]) == (
            False,
            True,
        )
        # Networks only partly inside the option's, live: they hold as set until the
        # restart, which keeps the part inside; the desk says both.
        part = desk(lab, "PUT", "/lab-network", {"networks": [INSIDE, HERE]})
        assert part["lab_networks"] == [INSIDE, HERE]
        origin = part["lab_networks_from"]
        assert (origin["until_restart"], origin["cut_from"]) == (True, [INSIDE, HERE])

    with lab_server(data, "--lab-network", ELSEWHERE) as lab:
        lab.sign_in("ann", "ann-password-12")
        cut = desk(lab)
        assert cut["lab_networks"] == [INSIDE]  # what holds: the part inside the option's
        origin = cut["lab_networks_from"]
        assert (origin["source"], origin["by"], origin["until_restart"]) == ("desk", "admin", False)
        assert (origin["command_line"], origin["cut_from"]) == (
            f"--lab-network {ELSEWHERE}",
            [INSIDE, HERE],  # what was saved, which the desk names beside it
        )
        taken = lab.rest("ann", "POST", "/api/lease")  # from 127.0.0.1: the part cut away
        assert (taken.status_code, taken.json()["error"]["message"]) == (403, OUTSIDE)
