"""Pre-flight in the browser: an instructor's table flags a move below it (the line in the
report, the path coloured in 3D), and the gate refuses an unsimulated program on the lab
robot, offering the simulation, and asks for it again once the instructor edited the cell."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Browser, expect

from melfa.vocab.refusals import Asked, Refusal
from tests.browser.conftest import Server, Session, serving
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(180)

PROGRAM = "SERVO ON\nMOV P1\nMOV P2\nEND\n"
POINTS = (
    "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,100.00,250.00,180.00,0.00,180.00)(7,0)\n"
)
TABLE = (
    '{"floor_z": 300, "boxes": [{"name": "feeder", "min": [-100, 300, 0], "max": [100, 500, 200]}]}'
)


def edit_cell(s: Session, text: str) -> None:
    page = s.page
    s.eval("() => document.getElementById('toasts').replaceChildren()")  # the welcome toast
    page.click("#cell-edit")
    page.click("#cell-tab-json")  # the cell's JSON, under the form
    page.fill("#cell-json", text)
    page.click("#cell-save")
    expect(page.locator("#cell-dialog")).to_have_count(0)


def test_preflight_flags_a_move_below_the_table(open_session: Any) -> None:
    admin: Session = open_session("admin")
    student: Session = open_session("alice")
    expect(student.page.locator("#cell-edit")).to_be_hidden()  # instructors edit the cell
    edit_cell(admin, TABLE)
    try:
        page = student.page
        page.reload()
        student.wait_ready()
        expect(page.locator("#view3d")).to_have_attribute("data-cell-floor", "300")
        expect(page.locator("#view3d")).to_have_attribute("data-cell-boxes", "1")
        student.set_program(PROGRAM)
        student.set_points(POINTS)
        page.click("#act-preflight")
        report = page.locator("#preflight")
        expect(report).to_have_attribute("data-passed", "false")
        finding = page.locator("#preflight-findings li.pf-error").first
        expect(finding).to_contain_text("table")
        expect(finding).to_have_attribute("data-line", "3")
        finding.locator(".pf-line").click()
        assert student.eval("() => window.melfa.editor.editor.getCursorPosition().row") == 2
        flagged = int(page.get_attribute("#view3d", "data-ghost-flagged") or "0")
        assert (
            flagged > 0 and int(page.get_attribute("#view3d", "data-ghost-points") or "0") > flagged
        )
        student.screenshot("preflight")
    finally:
        edit_cell(admin, '{"floor_z": 0, "boxes": []}')


@pytest.fixture(scope="module")
def gated(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with serving(tmp_path_factory.mktemp("melfa-gated"), "--require-simulation") as running:
        yield running


def test_the_gate_refuses_an_unsimulated_program_on_the_lab_robot(
    browser: Browser, gated: Server
) -> None:
    s = Session(browser, gated, "bob")
    try:
        s.login_api()
        page = s.page
        s.set_program(PROGRAM)
        s.set_points(POINTS)
        page.click("#act-load")
        refusal = page.locator(".toast", has_text="simulated run")
        expect(refusal).to_be_visible()
        s.screenshot("gate-refused")
        assert s.eval("() => window.melfa.loaded") is None  # nothing reached the robot
        refusal.get_by_role("button", name="Run pre-flight").click()
        expect(page.locator("#preflight")).to_have_attribute("data-passed", "true")
        expect(page.locator(".toast", has_text="Pre-flight passed")).to_be_visible()
        page.click("#act-load")
        expect(page.locator(".toast", has_text="Project loaded")).to_be_visible()
    finally:
        s.close()


def test_an_edited_cell_asks_for_preflight_again_before_a_run(
    browser: Browser, gated: Server
) -> None:
    """bob's program passed and is loaded; an instructor adds a fixture to the cell; his
    Run is refused in the student's words (the pass was in the old cell) with the one-click
    Run pre-flight, and runs once it passed again in the cell as it is."""
    bob, admin = Session(browser, gated, "bob"), Session(browser, gated, "admin")
    try:
        bob.login_api()
        admin.login_api()
        page = bob.page
        bob.set_program(PROGRAM)
        bob.set_points(POINTS)
        page.click("#act-preflight")
        expect(page.locator("#preflight")).to_have_attribute("data-passed", "true")
        page.click("#act-load")
        expect(page.locator(".toast", has_text="Project loaded")).to_be_visible()
        edit_cell(admin, FAR_FIXTURE)
        saved = admin.page.locator(".toast", has_text="Cell saved")
        expect(saved).to_contain_text("passes pre-flight again in this cell")  # the gate is on
        bob.eval("() => document.getElementById('toasts').replaceChildren()")
        page.click("#act-run")
        says, fix = Refusal.CELL_CHANGED.words(asked=Asked.RUN)  # pass again, run again
        refusal = page.locator(".toast", has_text=says)
        expect(refusal).to_be_visible()
        expect(refusal).to_contain_text(fix)
        bob.screenshot("gate-cell-changed")
        # The report below no longer says the lab robot may run it (its pass no longer counts)
        expect(page.locator("#preflight")).to_have_attribute("data-may-run", "false")
        expect(page.locator("#preflight-summary")).not_to_contain_text("may run")
        assert not ran_by(admin, "bob")
        refusal.get_by_role("button", name="Run pre-flight").click()
        passed = page.locator(".toast", has_text="Pre-flight passed")
        expect(passed).to_contain_text(Asked.RUN.after_fix)  # run again, not load again
        expect(page.locator("#preflight")).to_have_attribute("data-may-run", "true")
        page.click("#act-run")
        wait_until(lambda: ran_by(admin, "bob"), what="bob's run to be accepted")
    finally:
        edit_cell(admin, '{"floor_z": 0, "boxes": []}')
        bob.close()
        admin.close()


FAR_FIXTURE = (
    '{"floor_z": 0, "boxes": [{"name": "jig", "min": [-600, -600, 0], "max": [-500, -500, 80]}]}'
)
"""A box far from the program's path: the program still passes pre-flight in it."""


def ran_by(staff: Session, user: str) -> bool:
    """Whether ``user``'s Run was audited as accepted (the policy let it through)."""
    reply = staff.context.request.get(staff.server.url + "/api/audit?action=robot.run&limit=20")
    entries = reply.json()["entries"]
    return any(e["actor"] == user and e["result"] == "accepted" for e in entries)
