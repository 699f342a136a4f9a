"""The simulated cell in the browser: an instructor builds the lab's cell from the thesis's
bench (the form and the 3D view, JSON underneath), and a student's debug run of the pyramid
program moves the blocks in the 3D view, carried by the gripper and stacked."""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, expect

from tests.browser.conftest import SCREENSHOTS, Server, Session, serving
from tests.browser.test_debugger import gutter

pytestmark = pytest.mark.timeout(240)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A server of its own: this module changes the lab's cell."""
    with serving(tmp_path_factory.mktemp("melfa-cell")) as running:
        yield running


def close_up(s: Session, name: str) -> None:
    """The 3D view alone, the camera on the bench (as a student would orbit to it)."""
    s.eval(
        """() => { const v = window.melfa.view; v.camera.position.set(0.9, 0.75, 0.9);
                   v.controls.target.set(0.35, 0.15, 0); v.controls.update();
                   v.requestRender(); }"""
    )
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    s.page.mouse.move(0, 0)
    s.page.locator("#view3d").screenshot(path=str(SCREENSHOTS / f"{name}.png"))


HELD = "JSON.parse(document.getElementById('view3d').dataset.parts)['block 6'][3] === 1"
PROGRAM = (EXAMPLES / "pyramid.MB4").read_text(encoding="utf-8")


def line_of(text: str, after: int = 0) -> int:
    lines = PROGRAM.splitlines()
    return next(n for n in range(after + 1, len(lines) + 1) if lines[n - 1].strip() == text)


def parts(s: Session) -> dict[str, list[float]]:
    return dict(json.loads(s.page.get_attribute("#view3d", "data-parts") or "{}"))


def test_an_instructor_builds_the_cell_from_the_thesis_bench(browser: Browser, lab: Server) -> None:
    s = Session(browser, lab, "admin")
    try:
        s.login_api()
        page = s.page
        view = page.locator("#view3d")
        expect(view).to_have_attribute("data-cell-parts", "0")
        s.eval("() => document.getElementById('toasts').replaceChildren()")
        page.click("#cell-edit")
        page.click("#cell-template")
        # the 3D view shows the template at once, before anything is saved
        expect(view).to_have_attribute("data-cell-parts", "6")
        expect(view).to_have_attribute("data-cell-fixtures", "1")
        assert parts(s)["block 6"] == [350, -250, 225, 0]
        rows = page.locator("#cell-parts tr[data-name]")
        expect(rows).to_have_count(6)
        # move the top block 100 mm along X in the form: the 3D view follows as it is typed
        page.get_by_label("block 6: X", exact=True).fill("450")
        assert parts(s)["block 6"] == [450, -250, 225, 0]
        page.click("#cell-tab-json")
        cell = json.loads(page.input_value("#cell-json"))
        assert cell["parts"][5]["position"] == [450, -250, 225]
        assert cell["gripper"]["grip"] == 107.5
        # a mistake in the JSON is said in the instructor's words, and nothing is saved
        page.fill(
            "#cell-json",
            page.input_value("#cell-json").replace('"diameter": 54', '"diameter": -5', 1),
        )
        page.click("#cell-save")
        expect(page.locator("#cell-problem")).to_contain_text("diameter must be more than 0 mm")
        page.click("#cell-template")
        page.click("#cell-tab-form")
        expect(page.get_by_label("block 6: X", exact=True)).to_have_value("350")
        s.screenshot("cell-editor")
        page.click("#cell-save")
        expect(page.locator("#cell-dialog")).to_have_count(0)
        saved = s.context.request.get(lab.url + "/api/preflight").json()["cell"]
        assert [p["name"] for p in saved["parts"]] == [f"block {k}" for k in range(1, 7)]
        # a student sees the cell, and cannot edit it
        student = Session(browser, lab, "alice")
        try:
            student.login_api()
            expect(student.page.locator("#view3d")).to_have_attribute("data-cell-parts", "6")
            expect(student.page.locator("#cell-edit")).to_be_hidden()
        finally:
            student.close()
    finally:
        s.close()


def bench_as_the_lab_cell(browser: Browser, lab: Server) -> None:
    """The instructor's part of it through the API (the test above does it in the page)."""
    admin = browser.new_context()
    try:
        reply = admin.request.post(
            lab.url + "/api/session", data={"username": "admin", "password": lab.passwords["admin"]}
        )
        headers = {"X-CSRF-Token": reply.json()["csrf_token"]}
        bench = admin.request.get(lab.url + "/api/preflight/templates/thesis-bench").json()
        assert admin.request.put(lab.url + "/api/preflight/cell", data=bench, headers=headers).ok
    finally:
        admin.close()


def test_a_debug_run_moves_the_blocks_in_the_3d_view(browser: Browser, lab: Server) -> None:
    bench_as_the_lab_cell(browser, lab)
    s = Session(browser, lab, "bob")
    try:
        s.login_api()
        page = s.page
        s.set_program(PROGRAM)
        s.set_points((EXAMPLES / "pyramid.POS").read_text(encoding="utf-8"))
        s.eval("() => window.melfa.targets.choose('mine')")
        expect(page.locator("#debug-bar")).to_be_visible()
        page.wait_for_function("() => document.getElementById('view3d').dataset.cellParts === '6'")
        start = parts(s)
        # stop where the hand has just closed on the top block, and where it is about to
        # let it go on the pyramid's first place
        editor = "window.melfa.editor.editor"
        for line in (line_of("DLY 0.5"), line_of("HOPEN 1", after=30)):
            s.eval(f"(n) => {editor}.scrollToLine(n - 5, false, false, () => {{}})", line)
            gutter(page, line)
        page.select_option("#dbg-speed", "instant")
        page.click("#dbg-start")
        expect(page.locator("#dbg-status")).to_contain_text("breakpoint")
        page.wait_for_function(f"() => {HELD}")
        assert parts(s)["block 6"] == [350, -250, 225, 1]  # in the gripper, at the stack
        page.click("#dbg-continue")
        page.wait_for_function(
            f"() => {HELD} && JSON.parse(document.getElementById('view3d').dataset.parts)"
            "['block 6'][1] === 150"
        )
        # carried across the bench by the arm, still in the gripper
        assert parts(s)["block 6"] == [380, 150, 100, 1]
        close_up(s, "cell-carrying")
        for line in (line_of("DLY 0.5"), line_of("HOPEN 1", after=30)):
            s.eval(f"(n) => {editor}.scrollToLine(n - 5, false, false, () => {{}})", line)
            gutter(page, line)
        page.click("#dbg-continue")
        # the run ends with the six blocks stacked 3-2-1 where the program puts them
        expect(page.locator("#debug-panel")).to_contain_text("Finished", timeout=60_000)
        end = parts(s)
        assert end != start
        assert end["block 6"] == [380, 150, 100, 0]
        assert end["block 3"] == [407, 150, 125, 0]
        assert end["block 1"] == [434, 150, 150, 0]
        assert all(p[3] == 0 for p in end.values())
        # ending the session puts the blocks back where the cell has them
        page.click("#dbg-end")
        page.wait_for_function(
            "() => JSON.parse(document.getElementById('view3d').dataset.parts)"
            "['block 1'][2] === 100"
        )
        assert parts(s) == start
    finally:
        s.close()
