"""The guided first run (issue 16) in Debian's Chromium: a fresh student with an empty
workspace follows it to a moving arm and it ends; skipped, it stays skipped after a reload;
the user menu opens it again; a failed load says why and what to do; axe-core finds nothing
serious with it open; on a real robot it says the arm will move and points at STOP."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Browser, Page, expect

from tests.browser.conftest import (
    ADMIN_PASSWORD,
    Server,
    Session,
    axe_serious,
    free_the_robot,
    melfa_serve,
)
from tests.serving import free_port, stop_process
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(240)


def step(page: Page) -> str:
    return page.get_attribute("#guide", "data-step") or ""


def assert_beside_its_anchor(page: Page, anchor: str) -> None:
    """The callout is inside the window and does not cover what it points at (ringed)."""
    box = page.locator("#guide").bounding_box()
    target = page.locator(anchor).first.bounding_box()
    size = page.viewport_size
    assert box and target and size
    assert box["x"] >= 0 and box["y"] >= 0
    assert box["x"] + box["width"] <= size["width"] and box["y"] + box["height"] <= size["height"]
    right, bottom = box["x"] + box["width"], box["y"] + box["height"]
    overlap_w = min(right, target["x"] + target["width"]) - max(box["x"], target["x"])
    overlap_h = min(bottom, target["y"] + target["height"]) - max(box["y"], target["y"])
    assert overlap_w <= 0 or overlap_h <= 0, f"the guide covers {anchor}"
    rings = page.evaluate(
        "() => [...document.querySelectorAll('.guide-ring')]"
        ".map((r) => r.getBoundingClientRect().toJSON())"
    )
    around = [
        r
        for r in rings
        if r["x"] <= target["x"] and r["x"] + r["width"] >= target["x"] + target["width"]
    ]
    assert around, f"no ring around {anchor}"


def assert_covers_no_control(page: Page) -> None:
    """No button, tab, field or link under the callout (the editor's text and the 3D view
    aside): a student can still reach everything while it shows."""
    covered = page.evaluate(
        """() => {
        const g = document.getElementById('guide').getBoundingClientRect();
        const sel = 'button, [role=tab], select, input, a[href], [role=radio]';
        return [...document.querySelectorAll(sel)].filter((n) => n.offsetParent !== null
            && !n.closest('#guide, #editor, .view-stage, dialog, #toasts')).filter((n) => {
          const r = n.getBoundingClientRect();
          return r.width && r.height && r.left < g.right && r.right > g.left
            && r.top < g.bottom && r.bottom > g.top;
        }).map((n) => n.id || n.textContent.trim());
      }"""
    )
    assert not covered, f"the guide covers {covered}"


def test_a_fresh_student_follows_the_guide_to_a_moving_arm(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    server.add_user("gina")
    s: Session = open_session("gina", first_run=True)
    page = s.page
    free_the_robot(page, server)  # servo off and control free, as in a first hour
    # 1. The program and its comments, with the welcome project in the editor.
    expect(page.locator("#guide")).to_be_visible()
    assert step(page) == "program"
    assert "Welcome to melfa" in s.eval("() => window.melfa.workspace.program")
    expect(page.locator("#guide-live")).to_contain_text("Step 1 of 5")
    assert s.eval("() => document.activeElement.id") == "guide"  # the keyboard is in it
    assert_beside_its_anchor(page, "#editor")
    # A first-timer starts on their own simulated arm, never on the shared lab robot.
    expect(page.locator("#target-switch [data-target=mine]")).to_have_attribute(
        "aria-checked", "true"
    )
    page.keyboard.press("Tab")  # Skip guide
    page.keyboard.press("Tab")  # Next
    page.keyboard.press("Enter")
    # 2. Load project: the guide moves on when the load succeeded.
    wait_until(lambda: step(page) == "load", what="the load step")
    assert_beside_its_anchor(page, "#act-load")
    assert_covers_no_control(page)
    page.set_viewport_size({"width": 1024, "height": 700})
    page.wait_for_function("() => document.getElementById('guide').dataset.side")
    page.evaluate("() => window.dispatchEvent(new Event('resize'))")
    assert_beside_its_anchor(page, "#act-load")
    assert_covers_no_control(page)
    page.set_viewport_size({"width": 1366, "height": 768})
    page.evaluate("() => window.dispatchEvent(new Event('resize'))")
    page.click("#act-load")
    wait_until(lambda: step(page) == "run", timeout=30, what="the run step after the load")
    expect(page.locator("#guide")).to_contain_text("virtual robot")
    assert_beside_its_anchor(page, "#act-run")
    assert_covers_no_control(page)
    # 3. Run: the servo is off; the guide points at the message's own fix.
    start = s.joints()
    page.click("#act-run")
    wait_until(lambda: step(page) == "servo", what="the servo step")
    fix = page.locator("#toasts .toast-action", has_text="Turn on and retry")
    assert_beside_its_anchor(page, "#toasts .toast-action")
    fix.click()
    # 4. The arm moves and the marked line advances; the words name the editor's line.
    wait_until(lambda: step(page) == "watch", what="the watch step")
    wait_until(lambda: s.joints() != start, what="the arm to move")
    lines: set[str] = set()

    def runline() -> bool:
        lines.add(page.get_attribute("#editor", "data-run-line") or "")
        return len(lines - {""}) >= 3

    wait_until(runline, timeout=30, what="the running line to advance")
    # The label above the arm names the line the editor marks (not the controller's step).
    shown, pill = s.eval(
        "() => [document.getElementById('editor').dataset.runLine,"
        " document.getElementById('run-state').textContent]"
    )
    assert pill == f"running · line {shown}" or "line" not in pill, (pill, shown)
    # 5. The program ends by itself: the guide says what next, and Finish closes it.
    wait_until(lambda: step(page) == "done", timeout=90, what="the program to end")
    expect(page.locator("#guide")).to_contain_text("Points")
    expect(page.locator("#guide")).to_contain_text("Robot control")
    page.click("#guide-next")
    expect(page.locator("#guide")).to_be_hidden()
    assert s.eval("() => localStorage.getItem('melfa.guide.gina')") == "done"
    page.reload()
    s.wait_ready()
    page.wait_for_timeout(500)
    expect(page.locator("#guide")).to_be_hidden()


def test_skip_stays_skipped_the_menu_reopens_and_a_refused_load_says_why(
    open_session: Any, server: Server
) -> None:
    server.add_user("hugo")
    s: Session = open_session("hugo", first_run=True)
    page = s.page
    expect(page.locator("#guide")).to_be_visible()
    page.keyboard.press("Escape")  # focus is in the guide: Esc skips it
    expect(page.locator("#guide")).to_be_hidden()
    expect(page.locator("#guide-live")).to_contain_text("user menu")
    page.reload()
    s.wait_ready()
    page.wait_for_timeout(500)
    # Still the welcome program (which alone would open it), and still skipped.
    assert "Welcome to melfa" in s.eval("() => window.melfa.workspace.program")
    expect(page.locator("#guide")).to_be_hidden()
    # The user menu opens it again, from the first step; an emptied workspace gets the
    # welcome program back (there is nothing to lose).
    s.set_points("")
    s.set_program("")
    page.click("#user-button")
    page.get_by_role("menuitem", name="Show the first-run guide").click()
    expect(page.locator("#guide")).to_be_visible()
    assert step(page) == "program"
    assert "Welcome to melfa" in s.eval("() => window.melfa.workspace.program")
    # On the lab robot (the guide started her on My simulator), someone else has control:
    # the load is refused and the guide says why and what to do.
    expect(page.locator("#target-switch [data-target=mine]")).to_have_attribute(
        "aria-checked", "true"
    )
    page.click("#target-switch [data-target=lab]")
    page.wait_for_function("() => window.melfa.state && window.melfa.state.joints")
    free_the_robot(page, server)
    other: Session = open_session("carol")
    other.page.click("#lease-take")
    expect(page.locator("#lease-text")).to_contain_text("carol")
    page.click("#guide-next")
    page.click("#act-load")
    problem = page.locator("#guide .guide-problem")
    expect(problem).to_contain_text("carol holds the robot")
    expect(problem).to_contain_text("My simulator")
    assert step(page) == "load"
    page.click("#guide-skip")
    expect(page.locator("#guide")).to_be_hidden()
    other.page.click("#lease-release")


def test_axe_finds_nothing_serious_with_the_guide_open(open_session: Any, server: Server) -> None:
    server.add_user("ines")
    s: Session = open_session("ines", first_run=True)
    page = s.page
    expect(page.locator("#guide")).to_be_visible()
    page.wait_for_timeout(300)
    s.screenshot("first-run")
    found = axe_serious(page)
    assert not found, "\n".join(found)


@pytest.fixture(scope="module")
def real(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """`melfa serve --robot tcp://…`: a controller on a line, as the lab's arm is (the IDE
    cannot tell it from the real one, so it says "Real robot")."""
    data = tmp_path_factory.mktemp("melfa-real")
    port = free_port()
    sim_log = data / "sim.log"
    command = [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{port}"]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}  # its "listening" line reaches the log now
    with sim_log.open("w") as log:
        sim = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env)
        try:
            wait_until(lambda: "listening on" in sim_log.read_text(), 60, "melfa sim to listen")
            with melfa_serve(data, "--robot", f"tcp://127.0.0.1:{port}") as url:
                server = Server(url, data, {"admin": ADMIN_PASSWORD})
                server.add_user("alice")
                yield server
        finally:
            stop_process(sim)


def test_on_the_real_robot_the_guide_says_the_arm_moves_and_points_at_stop(
    browser: Browser, real: Server
) -> None:
    s = Session(browser, real, "alice", first_run=True)
    try:
        s.login_api()
        page = s.page
        expect(page.locator("#guide")).to_be_visible()
        # The guide starts on My simulator; on the lab's real arm, opened again, it warns.
        expect(page.locator("#target-switch [data-target=mine]")).to_have_attribute(
            "aria-checked", "true"
        )
        page.click("#guide-skip")
        page.click("#target-switch [data-target=lab]")
        expect(page.locator("#robot-badge")).to_have_text("Real robot")
        page.click("#user-button")
        page.click("#guide-open")
        expect(page.locator("#guide")).to_be_visible()
        page.click("#guide-next")
        page.click("#act-load")
        wait_until(lambda: step(page) == "run", timeout=30, what="the run step")
        guide = page.locator("#guide")
        expect(guide).to_contain_text("it will move")
        expect(guide).to_contain_text("STOP")
        assert_beside_its_anchor(page, "#act-run")
        assert_beside_its_anchor(page, "#estop")
    finally:
        s.close()
