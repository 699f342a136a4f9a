"""The browser IDE, end to end: a real `melfa serve` with the virtual robot, driven through
Debian's Chromium. Each test signs in its own browser context; the robot is shared, so
tests that move it leave it stopped (`stop_robot`)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session, free_the_robot
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(120)

LOOP_PROGRAM = """' Back and forth until stopped
SERVO ON
OVRD 20
*LOOP
MOV Pa
MOV Pb
GOTO *LOOP
"""
LOOP_POINTS = """DEF POS Pa=(400.00,-150.00,400.00,180.00,0.00,180.00)(7,0)
DEF POS Pb=(400.00,150.00,400.00,180.00,0.00,180.00)(7,0)
"""


def test_login_form_and_typo_suggestion_inline(open_session: Any, server: Server) -> None:
    server.add_user("newcomer")  # a first sign-in, whatever earlier modules did with alice
    s: Session = open_session("newcomer", login=False)
    page = s.page
    page.goto(s.server.url + "/")
    expect(page).to_have_url(s.server.url + "/login")
    page.fill("input[name=username]", "newcomer")
    page.fill("input[name=password]", s.server.passwords["newcomer"])
    page.click("button[type=submit]")
    s.wait_ready()
    expect(page.locator("#user-name")).to_have_text("newcomer")
    # An empty workspace starts with the welcome project and its three-step guide.
    assert "Welcome to melfa" in s.eval("() => window.melfa.workspace.program")
    assert "PPICK" in s.eval("() => window.melfa.workspace.points")

    page.click("#editor")
    page.keyboard.press("Control+A")
    page.keyboard.press("Delete")
    page.keyboard.type("DEF INTE M1\nWIHLE M1 < 3\nWEND\n")
    # The typo is suggested inline as one types (no save, no button): problems list,
    # gutter, underline. How soon is measured by bench/bench_web.py, not here.
    problem = page.locator("#problem-list li", has_text="did you mean WHILE?")
    expect(problem).to_be_visible()
    expect(page.locator(".ace_gutter-cell.ace_error")).to_have_count(1)
    marker = page.locator(".ace_marker-layer .melfa-err").first
    expect(marker).to_be_visible()
    box = marker.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + 8, box["y"] + box["height"] / 2)
    tip = page.locator("#tooltip")
    expect(tip).to_be_visible()
    expect(tip).to_contain_text("Replace with WHILE")
    expect(problem).not_to_contain_text("instead of")  # the fix does not repeat the headline
    s.screenshot("editor")


def test_live_check_can_be_switched_off_and_checked_manually(open_session: Any) -> None:
    s: Session = open_session("bob")
    page = s.page
    page.uncheck("#live-check")
    s.set_program("MOV P1\nGOSUB *NOWHERE\nHOPN 1\n")
    page.wait_for_timeout(800)
    expect(page.locator("#problem-list li")).to_have_count(0)
    page.click("#act-check")
    expect(page.locator("#problem-list li", has_text="HOPEN")).to_be_visible()
    expect(page.locator("#problem-list li", has_text="NOWHERE")).to_be_visible()
    page.click("#act-clear")
    expect(page.locator("#problem-list li")).to_have_count(0)
    # The choice is remembered across reloads.
    page.reload()
    s.wait_ready()
    expect(page.locator("#live-check")).not_to_be_checked()
    page.check("#live-check")


def test_open_mb4_strips_numbers_and_a_txt_is_refused(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    server.add_user("opener")  # its workspace starts with the welcome program
    s: Session = open_session("opener")
    page = s.page
    numbered = tmp_path / "demo.MB4"
    numbered.write_bytes(b"10 MOV P1\r\n20 GOTO 10\r\n30 END\r\n")
    # Over the work in the editor (the welcome program) it asks first; Cancel keeps it.
    # the welcome program arrives with the workspace (after the page is ready on a busy machine)
    page.wait_for_function("() => window.melfa.editor.text.trim() !== ''")
    before = s.eval("() => window.melfa.editor.text")
    page.set_input_files("#file-mb4", str(numbered))
    dialog = page.locator("#open-dialog")
    expect(dialog).to_be_visible()
    expect(dialog).to_contain_text("demo.MB4 replaces the program")
    page.click("#open-cancel")
    assert s.eval("() => window.melfa.editor.text") == before
    page.set_input_files("#file-mb4", str(numbered))
    page.click("#open-replace")
    expect(page.locator(".toast", has_text="Opened demo.MB4")).to_be_visible()
    text = s.eval("() => window.melfa.editor.text")
    assert text.startswith("10 MOV P1\nGOTO 10\nEND")  # jump target kept, others stripped
    notes = tmp_path / "notes.txt"
    notes.write_text("MOV P2\n")
    page.set_input_files("#file-mb4", str(notes))
    expect(page.locator(".toast.error", has_text="notes.txt was not opened")).to_be_visible()
    assert s.eval("() => window.melfa.editor.text") == text
    # The points tab refuses a program file the same way.
    page.click("#tab-points")
    page.set_input_files("#file-pos", str(numbered))
    expect(page.locator(".toast.error", has_text="demo.MB4 was not loaded")).to_be_visible()
    # The replaced program is a named revision; History compares it with now.
    page.click("#tab-editor")
    page.click("#history-button")
    saved = page.locator("#history-list li").last  # the oldest: the welcome program
    expect(saved).to_be_visible()
    saved.get_by_role("button", name="Compare").click()
    diff = page.locator("#diff-dialog")
    expect(diff).to_be_visible()
    expect(diff.locator(".del").first).to_contain_text("Welcome to melfa")
    expect(diff.locator(".add", has_text="GOTO 10")).to_be_visible()
    s.screenshot("history-diff")
    diff.get_by_role("button", name="Close").click()


def test_points_by_dialog_and_by_importing_the_current_position(
    open_session: Any,
) -> None:
    s: Session = open_session("alice")
    page = s.page
    s.set_points("")
    page.click("#tab-points")
    page.click("#point-add")
    dialog = page.locator("#point-dialog")
    expect(dialog).to_be_visible()
    page.fill("#pt-name", "Xbad")
    for i, value in enumerate(["300", "100", "250", "180", "0", "180"]):
        page.fill(f"#pt-v{i}", value)
    expect(page.locator("#pt-problems")).to_contain_text("starts with P")
    page.fill("#pt-name", "Pfar")
    page.fill("#pt-v0", "5000")  # beyond the RV-6S's reach: a warning, not an error
    expect(page.locator("#pt-problems .warn-text")).to_contain_text("reach")
    page.fill("#pt-v0", "abc")
    expect(page.locator("#pt-problems")).to_contain_text("X must be a number")
    page.fill("#pt-v0", "300")
    page.fill("#pt-name", "Pdrop")
    expect(page.locator("#pt-problems")).to_contain_text("Reachable")
    page.click("#pt-ok")
    expect(dialog).to_be_hidden()
    row = page.locator("#points-body tr[data-point=Pdrop]")
    expect(row).to_contain_text("300.00")
    expect(row).to_contain_text("✓ ok")

    # Import where the robot stands.
    page.click("#point-add")
    page.fill("#pt-name", "Phere")
    page.click("#pt-import")
    pose = s.pose()
    assert float(page.input_value("#pt-v0")) == pytest.approx(pose[0], abs=0.01)
    assert float(page.input_value("#pt-v2")) == pytest.approx(pose[2], abs=0.01)
    page.click("#pt-ok")
    expect(page.locator("#points-body tr")).to_have_count(2)
    points = s.eval("() => window.melfa.workspace.points")
    assert "DEF POS Pdrop=(300.00,100.00,250.00,180.00,0.00,180.00)(7,0)" in points
    assert "DEF POS Phere=(" in points
    expect(page.locator("#points-count")).to_have_text("2")
    # Points count as declared in the program.
    page.click("#tab-editor")
    s.set_program("MOV Pdrop\nMOV Phere\nMOV Pnone\n")
    expect(page.locator("#problem-list li", has_text="Pnone")).to_be_visible()
    expect(page.locator("#problem-list li")).to_have_count(1)


def test_load_project_run_and_stop_overtakes(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s: Session = open_session("bob")
    page = s.page
    free_the_robot(page, server)  # servo off, as a student finds it
    s.eval(
        "() => { window.__progress = []; window.melfa.live.on('progress', (m) => "
        "window.__progress.push([m.sent, m.total])); }"
    )
    s.set_points(LOOP_POINTS)
    s.set_program(LOOP_PROGRAM)
    page.click("#act-load")
    expect(page.locator(".toast", has_text="Project loaded")).to_be_visible(timeout=30_000)
    progress = s.eval("() => window.__progress")
    assert progress, "no progress events"
    assert all(0 <= sent <= total for sent, total in progress)
    assert progress[-1][0] == progress[-1][1]
    expect(page.locator("#upload-progress")).to_have_attribute("value", "1")

    start = s.joints()
    page.click("#act-run")
    # The servo is off: the refusal says so in plain words, keeps the code, offers the fix.
    refused = page.locator(".toast.error", has_text="The servo is off")
    expect(refused).to_be_visible()
    expect(refused.locator(".code")).to_have_text("L2000")
    refused.get_by_role("button", name="Turn on and retry").click()
    wait_until(lambda: s.joints() != start, what="the 3D view's joints to change")
    wait_until(lambda: int(page.get_attribute("#view3d", "data-path-points") or 0) > 3, what="path")
    expect(page.locator("#run-state")).to_contain_text("running")
    s.screenshot("run")

    page.click("#estop")
    wait_until(lambda: s.eval("() => window.melfa.state.running") is False, what="stop")
    page.wait_for_timeout(400)
    stopped = s.joints()
    page.wait_for_timeout(600)
    assert s.joints() == stopped
    expect(page.locator("#run-state")).not_to_contain_text("running")


def test_jog_with_held_keys_moves_and_stops_on_release(open_session: Any, stop_robot: None) -> None:
    s: Session = open_session("carol")
    page = s.page
    page.click("#tab-robot")
    page.click("#servo-on")
    wait_until(lambda: s.eval("() => window.melfa.state.servo") is True, what="servo on")
    expect(page.locator("#jog-speed")).to_have_attribute("max", "10")  # the server's ceiling
    canvas = page.locator("#jog-canvas")
    canvas.focus()
    before = s.pose()
    page.keyboard.down("w")
    expect(canvas).to_have_attribute("data-lit", "w")
    wait_until(lambda: s.pose()[0] > before[0] + 2, what="+X jog")
    page.keyboard.up("w")
    expect(canvas).to_have_attribute("data-lit", "")
    wait_until(lambda: s.eval("() => !window.melfa.state.jogging"), what="jog end")
    page.wait_for_timeout(300)
    after, joints = s.pose(), s.joints()
    page.wait_for_timeout(600)
    # Stopped: the joints read back are unchanged. (Not the pose: the service alternates
    # between the pose read from the controller and one computed from the joints.)
    assert s.joints() == joints, "the arm kept moving after the key was released"
    assert abs(after[1] - before[1]) < 1 and abs(after[2] - before[2]) < 1

    page.keyboard.down("ArrowUp")
    wait_until(lambda: s.pose()[2] > after[2] + 2, what="+Z jog")
    page.keyboard.up("ArrowUp")
    wait_until(lambda: s.eval("() => !window.melfa.state.jogging"), what="jog end")
    # Holding the key then leaving the page (blur) stops it too.
    page.keyboard.down("s")
    wait_until(lambda: s.eval("() => window.melfa.state.jogging") is True, what="jog start")
    s.eval("() => window.dispatchEvent(new Event('blur'))")
    wait_until(lambda: s.eval("() => !window.melfa.state.jogging"), what="jog end on blur")
    page.keyboard.up("s")
    expect(page.locator("#lease-text")).to_contain_text("you")


def test_reload_keeps_unsaved_work(open_session: Any) -> None:
    s: Session = open_session("carol")
    page = s.page
    page.click("#editor")
    page.keyboard.press("Control+End")
    page.keyboard.type("' typed just before the reload\n")
    page.reload()  # before the autosave had a chance
    s.wait_ready()
    expect(page.locator(".ace_content")).to_contain_text("typed just before the reload")
    # … and it reaches the server.
    stored = "(id) => fetch(`/api/workspaces/${id}`).then((r) => r.json()).then((w) => w.program)"
    ws_id = s.eval("() => window.melfa.workspace.id")
    wait_until(lambda: "typed just before" in s.eval(stored, ws_id), what="autosave")
    expect(page.locator("#save-state")).to_contain_text("Saved")


def test_history_restores_a_revision(open_session: Any) -> None:
    s: Session = open_session("bob")
    page = s.page
    s.set_program("' version one\nEND\n")
    page.evaluate("() => window.melfa.workspace.save('save')")
    s.set_program("' version two\nEND\n")
    page.evaluate("() => window.melfa.workspace.save('save')")
    page.click("#history-button")
    first = page.locator("#history-list li").nth(1)
    first.get_by_role("button", name="Restore").click()
    expect(page.locator(".ace_content")).to_contain_text("version one")


def test_second_user_sees_the_first_holding_the_robot(open_session: Any, server: Server) -> None:
    alice: Session = open_session("alice")
    bob: Session = open_session("bob")
    free_the_robot(alice.page, server)  # the shared server's earlier tests may hold it
    alice.page.click("#lease-take")
    expect(alice.page.locator("#lease-text")).to_contain_text("you")
    expect(bob.page.locator("#lease-text")).to_contain_text("alice")
    expect(bob.page.locator("#lease-take")).to_be_hidden()
    # Bob may not move it, but he can always STOP.
    bob.page.click("#act-run")
    bob.page.click("#run-anyway")  # Run asks first: the slot does not hold his text
    expect(bob.page.locator(".toast.error")).to_contain_text("alice holds the robot")
    bob.page.click("#estop")
    expect(bob.page.locator(".toast", has_text="Stop sent")).to_be_visible()
    alice.page.click("#lease-release")
    expect(bob.page.locator("#lease-text")).to_contain_text("free")


def test_screenshots_of_each_tab(open_session: Any, server: Server, stop_robot: None) -> None:
    """docs/screenshots/*.png at 1366×768 with the bundled pyramid example."""
    root = Path(__file__).resolve().parents[2]
    s: Session = open_session("admin")
    page = s.page
    free_the_robot(page, server)  # the servo off whatever earlier tests left: Run asks first
    s.set_points((root / "examples/pyramid.POS").read_text(encoding="utf-8"))
    s.set_program((root / "examples/pyramid.MB4").read_text(encoding="utf-8"))
    expect(page.locator("#diag-summary")).to_be_empty()
    page.click("#act-load")
    expect(page.locator(".toast", has_text="Project loaded")).to_be_visible(timeout=30_000)
    page.click("#act-run")
    page.locator(".toast.error").get_by_role("button", name="Turn on and retry").click()
    wait_until(lambda: int(page.get_attribute("#view3d", "data-path-points") or 0) > 40, 20, "path")
    page.evaluate("() => document.querySelectorAll('.toast').forEach((t) => t.remove())")
    s.screenshot("ide-editor")
    page.click("#tab-points")
    s.screenshot("ide-points")
    page.click("#point-add")
    page.fill("#pt-name", "Pplace")
    page.click("#pt-import")
    page.wait_for_timeout(500)
    s.screenshot("ide-point-dialog")
    page.click("#pt-cancel")
    page.click("#tab-robot")
    page.locator("#jog-canvas").focus()
    s.screenshot("ide-robot")
    page.set_viewport_size({"width": 1920, "height": 1080})
    page.click("#tab-editor")
    page.wait_for_timeout(300)
    s.screenshot("ide-1920")
    page.click("#estop")
    assert json.loads(page.get_attribute("#view3d", "data-joints") or "[]")
