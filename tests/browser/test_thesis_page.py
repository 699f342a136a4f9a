"""The thesis's web page, as a roslibjs client of `melfa serve --rosbridge-port`: a page
from another origin (as the thesis's own bottle server was) sends exactly what
biellls/arm_control_web's page sends, in its order, with a personal access token in the
rosbridge URL, against the thesis mode: load project, run, jog (the arm moves the way the
page's keys say), import the pose into the point form, move to a point.

The page is tests/browser/pages/thesis_client.html (melfa's own code doing what the
thesis's page does); roslibjs is the pinned npm bundle the server vendors. A small HTTP
server on another loopback port serves both, as the thesis's page came from its own server
on the rosbridge machine. No network."""

from __future__ import annotations

import http.server
import json
import math
import re
import subprocess
import sys
import threading
import time
import urllib.request
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, Page

from tests.browser.conftest import ROOT, melfa_serve
from tests.serving import free_port
from tests.waiting import wait_until

PAGE = Path(__file__).parent / "pages" / "thesis_client.html"
# The thesis's example program (chapter 7.1.1), as its editor holds it (numbers stripped),
# and its points (chapter 7.2, test 3).
EDITOR = "SERVO ON\nOVRD 30\nSPD 10\nMOV PPIRAM ' to the pyramid\nMOV PINIC\nEND"
POINTS = [
    "DEF POS PPIRAM=(417.61,16.40,180.00,180.00,0.00,180.00)(7,0)",
    "DEF POS PINIC=(524.49,80.98,614.92,-179.99,0.00,-93.07)(7,0)",
]
JOG_STEP_MM = 20.0  # the thesis's TOOL_INCREMENT (0.02 m)


def roslib_js() -> Path:
    found = sorted((ROOT / "src/melfa/web/static/vendor").glob("roslib-*/roslib.js"))
    if not found:  # pragma: no cover - scripts/build-frontend makes it
        pytest.skip("roslibjs is not vendored: run scripts/build-frontend")
    return found[-1]


@dataclass(frozen=True)
class Melfa:
    web: str
    bridge_port: int
    token: str

    def get(self, path: str) -> Any:
        """A REST read with the same personal access token (Authorization: Bearer)."""
        request = urllib.request.Request(
            self.web + path, headers={"Authorization": f"Bearer {self.token}"}
        )
        with urllib.request.urlopen(request, timeout=30) as reply:
            return json.loads(reply.read())

    def pose(self) -> list[float]:
        return list(self.get("/api/robot/state")["pose"])

    def wait_pose(self, want: Callable[[list[float]], bool], timeout: float = 90.0) -> list[float]:
        """The pose once it satisfies ``want`` as measured by the controller (PPOSF: the
        pose computed from two-decimal joints while moving may differ by ~0.1 mm)."""

        def there() -> list[float] | None:
            state = self.get("/api/robot/state")
            pose = list(state["pose"])
            return pose if state["pose_measured"] and want(pose) else None

        return wait_until(there, timeout, what=lambda: f"the arm; it is at {self.pose()}")


def cli(data: Path, *args: str) -> str:
    out = subprocess.run(
        [sys.executable, "-m", "melfa", "users", *args, "--data", str(data)],
        capture_output=True,
        text=True,
        check=True,
        timeout=60,
    )
    return out.stdout.strip().splitlines()[-1]


@pytest.fixture(scope="module")
def melfa(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Melfa]:
    """`melfa serve --rosbridge-port … --rosbridge-mode thesis`, and a lab account with a
    token made by `melfa users token`."""
    data = tmp_path_factory.mktemp("melfa-thesis")
    bridge = free_port()
    with melfa_serve(data, "--rosbridge-port", str(bridge), "--rosbridge-mode", "thesis") as web:
        cli(data, "add", "lab", "--generate")
        yield Melfa(web, bridge, cli(data, "token", "lab", "--label", "thesis page"))


@pytest.fixture(scope="module")
def origin() -> Iterator[str]:
    """The page's own web server: thesis.html and roslib.js, nothing else."""
    files = {"/thesis.html": (PAGE, "text/html"), "/roslib.js": (roslib_js(), "text/javascript")}

    class Files(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            found = files.get(self.path)
            if found is None:
                self.send_error(404)
                return
            body = found[0].read_bytes()
            self.send_response(200)
            self.send_header("Content-Type", found[1])
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: object) -> None:
            pass

    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Files)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{httpd.server_address[1]}"
    finally:
        httpd.shutdown()
        httpd.server_close()


@pytest.fixture
def page(browser: Browser, origin: str) -> Iterator[Page]:
    context = browser.new_context()
    context.set_default_timeout(30_000)
    errors: list[str] = []
    page = context.new_page()
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(f"{origin}/thesis.html")
    yield page
    context.close()
    assert not errors, errors


def next_second() -> None:
    """The page stamps moves in whole seconds and the node drops a move not newer than the
    last finished one (the thesis's rule), so a new key press waits for the next second."""
    time.sleep(1.05 - time.time() % 1)


def press(page: Page, key: str) -> None:
    page.focus("#keys")
    page.keyboard.down(key)
    page.keyboard.up(key)


def test_the_thesis_page_drives_the_robot_through_rosbridge(page: Page, melfa: Melfa) -> None:
    page.evaluate(
        "(url) => window.connect(url)", f"ws://127.0.0.1:{melfa.bridge_port}/?token={melfa.token}"
    )
    page.wait_for_function("() => window.connected || window.lastError")
    assert page.evaluate("() => window.connected"), page.evaluate("() => window.lastError")

    # Load project, then Run (the thesis's buttons; messages go out back to back).
    page.evaluate("([text, points]) => window.loadProject(text, points)", [EDITOR, POINTS])
    page.evaluate("() => window.run()")
    pinic = (524.49, 80.98, 614.92)
    melfa.wait_pose(lambda p: math.dist(p[:3], pinic) < 0.05)  # MOV PPIRAM, then MOV PINIC
    state = melfa.get("/api/robot/state")
    assert state["alarm"] is None, state["alarm"]

    # Jog: ↑ moves up 20 mm along the base Z, w moves 20 mm along the base +X.
    start = melfa.pose()
    next_second()
    press(page, "ArrowUp")
    up = melfa.wait_pose(lambda p: p[2] > start[2] + JOG_STEP_MM - 0.05)
    assert up[:3] == pytest.approx([start[0], start[1], start[2] + JOG_STEP_MM], abs=0.05)
    next_second()
    press(page, "w")
    forward = melfa.wait_pose(lambda p: p[0] > up[0] + JOG_STEP_MM - 0.05)
    assert forward[:3] == pytest.approx([up[0] + JOG_STEP_MM, up[1], up[2]], abs=0.05)

    # Import the current robot position into the point form: mm and degrees, X to Yaw.
    page.evaluate("() => window.importPose()")
    page.wait_for_function("() => document.getElementById('j6input').value !== ''")
    form = [float(page.input_value(f"#j{i}input")) for i in range(1, 7)]
    pose = melfa.pose()
    assert form[:3] == pytest.approx(pose[:3], abs=0.01)
    scale = math.pi / 3.14159  # the page's own π
    for shown, angle in zip(form[3:], pose[3:], strict=True):
        assert math.cos(math.radians(shown / scale - angle)) == pytest.approx(1, abs=1e-7)
    assert len(page.evaluate("() => window.received")) == 1  # answers only when asked

    # Move to a point (its "Move" button).
    page.evaluate("(line) => window.moveToPoint(line)", POINTS[0])
    melfa.wait_pose(lambda p: math.dist(p[:3], (417.61, 16.40, 180.00)) < 0.05)

    sent = page.evaluate("() => window.sent")
    program = [f"{10 * (i + 1)} {line}" for i, line in enumerate(EDITOR.split("\n"))]
    program[3] = "40 MOV PPIRAM"  # the page strips the comment
    expected = [
        "---DELETE---",
        "---LOAD PROGRAM BEGIN---",
        *program,
        "---LOAD PROGRAM END---",
        "---LOAD POINTS BEGIN---",
        *POINTS,
        "---LOAD POINTS END---",
        "---RUN PROGRAM---",
        "---MOV TOOL +Z---<t>",
        "---MOV TOOL +X---<t>",
        "---REQUEST TOOL POSE---",
        "---MOVE TOOL STATE---",
        "(417.61,16.40,180.00,180.00,0.00,180.00)",
    ]
    assert [re.sub(r"---\d+$", "---<t>", s) for s in sent] == expected
