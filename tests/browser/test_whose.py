"""Two or more people on the one lab robot: whose program is in the slot, in the IDE.

A third student whose load was refused presses *Run*: the IDE asks first, naming whose
program the robot holds, and her editor never marks lines of bob's run. The words after
STOP → *Move to* → arrival come from the service's one activity: "Moving to P3" while the
arm goes (never "Running … line N" with the program paused), "At P3" only once it stands
still. A run-time ``ERROR 9100`` on the lab robot marks its line and is told as the
student's own error; the alarm banner's *Reset alarm* takes a real mouse press and
release while state messages keep coming.
"""

from __future__ import annotations

import re
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from tests.browser.conftest import SIGNED_OUT, Server, Session, free_the_robot
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(180)

POINTS = (
    "DEF POS P1=(400.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,150.00,350.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P3=(350.00,-150.00,300.00,180.00,0.00,180.00)(7,0)\n"
)
LOOP = "10 MOV P1\n20 MOV P2\n30 GOTO 10\n"


def servo_said_yes(s: Session) -> None:
    """This student agreed before that moves switch the servo on (fixes.js)."""
    s.eval("() => sessionStorage.setItem('melfa.servo-on-for-moves', '1')")


def load(s: Session, program: str, points: str = POINTS) -> None:
    s.set_points(points)
    s.set_program(program)
    s.page.click("#act-load")
    s.saw_toast("Project loaded")


def loaded_by(open_session: Any, server: Server, user: str, program: str) -> Session:
    """``user`` on a free robot, their ``program`` loaded, moves allowed to switch the servo on."""
    s: Session = open_session(user)
    free_the_robot(s.page, server)
    servo_said_yes(s)
    load(s, program)
    return s


def activity(page: Page) -> str:
    return page.text_content("#activity-text") or ""


def test_a_third_students_run_after_a_refused_load_asks_and_names_whose_program(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    bob: Session = open_session("bob")
    free_the_robot(bob.page, server)
    servo_said_yes(bob)
    load(bob, LOOP)
    expect(bob.page.locator("#slot-info")).to_have_attribute("data-owner", "mine")
    bob.page.click("#act-run")  # his own text: no question
    wait_until(lambda: bob.page.get_attribute("#editor", "data-run-line"), what="bob's line")
    bob.page.click("#act-stop")
    bob.page.click("#lease-release")

    carol: Session = open_session("carol")
    page = carol.page
    servo_said_yes(carol)
    slot = page.locator("#slot-info")
    expect(slot).to_have_attribute("title", re.compile("bob's program is in the robot"))
    expect(slot).to_have_text("bob's program")  # whose, first: whole in the view's head
    page.set_viewport_size({"width": 1024, "height": 700})
    assert page.evaluate(  # at 1024 px it said "bob's progr…" ("Your program is i…")
        "() => { const t = document.querySelector('#slot-info .slot-text');"
        " return t.scrollWidth <= t.clientWidth; }"
    )
    page.set_viewport_size({"width": 1366, "height": 768})
    # Her load is refused (an error on line 2); the list keeps the warning of line 3 too.
    carol.set_points(POINTS)
    carol.set_program("MOV P1\nMOOV P2\nMOV PNOWHERE\nEND\n")
    page.click("#act-load")
    expect(page.locator(".toast.error", has_text="Not loaded")).to_be_visible()
    # Each problem is listed with its line: the message does not end "(line 2:1)" as well
    expect(page.locator(".toast.error", has_text="Not loaded")).not_to_contain_text("(line 2")
    problems = page.locator("#problem-list li")
    expect(problems.filter(has_text="error")).to_have_count(1)
    expect(problems.filter(has_text="PNOWHERE")).to_have_count(1)
    expect(page.locator("#slot-info")).to_have_attribute("data-owner", "theirs")

    # Run asks first, naming whose program is in the slot; Cancel runs nothing.
    page.click("#act-run")
    dialog = page.locator("#run-dialog")
    expect(dialog).to_be_visible()
    expect(dialog.locator("h2")).to_have_text("Run bob's program?")
    expect(dialog).to_contain_text("The robot holds bob's program")
    expect(page.locator("#run-anyway")).to_have_text("Run bob's program")
    page.click("#run-cancel")
    expect(dialog).to_be_hidden()
    assert carol.eval("() => window.melfa.state.running") is False

    # She runs it knowingly: bob's program moves the arm, and her editor marks nothing.
    page.click("#act-run")
    page.click("#run-anyway")
    lines: set[str] = set()

    def running() -> bool:
        lines.add(page.get_attribute("#editor", "data-run-line") or "")
        return bool(carol.eval("() => window.melfa.state.program_running"))

    wait_until(running, what="bob's program to run for carol")
    for _ in range(20):  # a good look while it runs (state messages keep coming)
        seq = carol.eval("() => window.melfa.state.seq")
        page.wait_for_function("(n) => window.melfa.state.seq > n", arg=seq)
        lines.add(page.get_attribute("#editor", "data-run-line") or "")
    assert lines == {""}, f"carol's editor marked bob's run: {lines}"
    # bob's own page marks his lines as his program runs for her.
    wait_until(lambda: bob.page.get_attribute("#editor", "data-run-line"), what="bob's marked line")
    carol.screenshot("whose-run-asked")
    page.click("#estop")


def test_state_words_after_stop_move_to_and_arrival(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s = loaded_by(open_session, server, "alice", LOOP)
    page = s.page
    page.click("#act-run")
    wait_until(lambda: s.eval("() => window.melfa.state.line") == 20, what="the run under way")
    page.click("#act-stop")
    page.wait_for_function("() => window.melfa.state.activity === 'paused'")
    # Every word the activity line says from the click on Move to on, with the state then.
    s.eval(
        """() => {
        window.__said = [];
        const node = document.getElementById('activity-text');
        const note = () => window.__said.push([node.textContent, window.melfa.state.running,
          window.melfa.state.moving, window.melfa.state.activity]);
        const what = {childList: true, characterData: true, subtree: true};
        new MutationObserver(note).observe(node, what);
        const move = document.getElementById('goto-move');
        move.addEventListener('click', () => { window.__said = []; }, {capture: true});
      }"""
    )
    page.click("#tab-robot")
    page.select_option("#goto-point", "P3")
    page.click("#goto-move")
    page.wait_for_function("() => window.melfa.state.activity === 'at'", timeout=30_000)
    expect(page.locator("#activity-text")).to_have_text("At P3")
    said = s.eval("() => window.__said")
    texts = [text for text, *_ in said]
    assert not [t for t in texts if t.startswith(("Running", "Paused"))], texts
    assert "Moving to P3" in texts, texts
    first_at = texts.index("At P3")
    assert first_at > texts.index("Moving to P3"), texts
    # "At P3" only once the arm stands still, and the arm did move in between.
    _, running, moving, code = said[first_at]
    assert (running, moving, code) == (False, False, "at"), said[first_at]
    assert any(r for _, r, _, a in said[:first_at]), said
    s.screenshot("whose-at-point")


def test_a_run_time_error_on_the_lab_robot_marks_its_line(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    program = "MOV P1\nMOV P2\n' the part is missing: stop\nERROR 9100\nEND\n"
    s = loaded_by(open_session, server, "alice", program)
    page = s.page
    page.click("#act-run")
    page.wait_for_selector("#editor[data-error-line='4']", timeout=30_000)
    page.click("#tab-robot")  # the alarm banner, above the controls
    alarm = page.locator("#alarm")
    expect(alarm).to_contain_text("Error L9100 at line 4")
    expect(alarm).to_contain_text("Your program stopped itself: its ERROR 9100 statement ran")
    assert "controller refused" not in (alarm.text_content() or "")
    expect(page.locator("#activity-text")).to_contain_text("Alarm")
    s.screenshot("whose-runtime-error")

    # Reset alarm: a real press and release, with state messages arriving in between.
    button = page.locator("#alarm-fix")
    box = button.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    seq = s.eval("() => window.melfa.state.seq")
    page.wait_for_function("(n) => window.melfa.state.seq >= n + 3", arg=seq)
    page.mouse.up()
    page.wait_for_function("() => !window.melfa.state.alarm", timeout=15_000)
    expect(alarm).to_be_hidden()
    expect(page.locator("#editor")).not_to_have_attribute("data-error-line", "4")


def test_a_misspelt_point_offers_the_close_name_first(open_session: Any) -> None:
    s: Session = open_session("alice")
    page = s.page
    home = "DEF POS Phome=(400.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    row = s.checked_problem(home, "MOV Phom\nEND\n", "Phom is not defined")
    expect(row).to_contain_text("Did you mean Phome?")
    buttons = row.locator(".fixes button")
    expect(buttons.first).to_have_text("Replace with Phome")  # the first fix is the close name
    buttons.first.click()
    wait_until(lambda: s.eval("() => window.melfa.editor.text").startswith("MOV Phome\n"))
    page.click("#act-check")
    expect(page.locator("#problem-list li", has_text="Phom")).to_have_count(0)


def test_the_problems_list_shows_a_usable_number_of_rows(open_session: Any) -> None:
    s: Session = open_session("alice")
    page = s.page
    s.set_points("")
    s.set_program("".join(f"MOV PM{i}\n" for i in range(12)) + "END\n")
    page.click("#act-check")
    expect(page.locator("#problem-list li")).to_have_count(12)
    for width, height in ((1366, 768), (1024, 700)):
        page.set_viewport_size({"width": width, "height": height})
        shown = s.eval(
            """() => {
            const box = document.getElementById('problems').getBoundingClientRect();
            return [...document.querySelectorAll('#problem-list li')].filter((li) => {
              const r = li.getBoundingClientRect();
              return r.top >= box.top - 1 && r.bottom <= box.bottom + 1;
            }).length;
          }"""
        )
        editor = page.locator("#editor").bounding_box()
        assert shown >= 5, (width, height, shown)
        assert editor and editor["height"] >= 200, (width, height, editor)  # and room to type
        s.screenshot(f"problems-{width}")
    page.set_viewport_size({"width": 1366, "height": 768})


def test_sign_out_leaves_no_program_text_in_the_browser(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s: Session = open_session("carol")
    free_the_robot(s.page, server)
    load(s, "MOV P1\n' carol's secret solution\nEND\n")
    stored = s.eval("() => JSON.stringify(Object.assign({}, localStorage))")
    assert "secret solution" in stored  # kept for the running line across a reload
    s.page.click("#user-button")
    s.page.click("#logout")
    s.page.wait_for_url(SIGNED_OUT)
    stored = s.eval("() => JSON.stringify(Object.assign({}, localStorage))")
    assert "secret solution" not in stored, stored


def test_the_editor_follows_the_running_line(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    filler = "".join(f"' step {i} of the long way round\n" for i in range(50))
    program = f"MOV P1\n{filler}MOV P2\nMOV P3\nEND\n"  # P2 on line 52, off the first screen
    s = loaded_by(open_session, server, "alice", program)
    page = s.page
    s.eval("() => window.melfa.editor.editor.gotoLine(1, 0, false)")
    page.click("#act-run")
    page.wait_for_function(
        "() => Number(document.getElementById('editor').dataset.runLine || 0) >= 52",
        timeout=30_000,
    )
    shown = s.eval(
        """() => {
        const e = window.melfa.editor.editor;
        const row = Number(document.getElementById('editor').dataset.runLine) - 1;
        return [e.getFirstVisibleRow(), row, e.getLastVisibleRow()];
      }"""
    )
    first, row, last = shown
    assert first <= row <= last, shown
    page.click("#estop")


def test_a_run_stopped_by_a_reload_says_so_when_the_page_is_back(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s = loaded_by(open_session, server, "alice", LOOP)
    page = s.page
    page.click("#act-run")
    page.wait_for_function("() => window.melfa.state && window.melfa.state.program_running")
    page.reload()  # her only page closes while the arm moves: the service stops it
    s.wait_ready()
    # The toast may come and go (4 s) while the page gets ready on a busy machine.
    told = s.saw_toast("Your run was stopped")
    assert "every page of yours had closed" in told


def test_an_open_menu_lies_above_the_toasts(open_session: Any, server: Server) -> None:
    """Errors stay until closed, and the toasts lie where the user menu opens: a student with
    four unread errors could not reach Sign out (CI, a toast took the click for 10 s)."""
    s: Session = open_session("carol")
    s.eval(
        """async () => { const { toast } = await import('/static/js/ui.js');
           for (let i = 0; i < 4; i++) toast('Something went wrong', {kind: 'error',
             text: 'A long explanation of what went wrong and what to do about it now'}); }"""
    )
    for button, menu in (("#user-button", "#user-menu"), ("#ws-switch", "#ws-menu")):
        if not s.page.locator(button).is_visible():
            continue
        s.page.click(button)
        covered = s.eval(
            """(menu) => [...document.querySelectorAll(`${menu} [role=menuitem], ${menu} button`)]
                 .filter((e) => e.getClientRects().length)
                 .filter((e) => { const r = e.getBoundingClientRect();
                   const x = r.left + r.width / 2, y = r.top + r.height / 2;
                   const hit = document.elementFromPoint(x, y);
                   return !(hit && e.contains(hit)); })
                 .map((e) => e.textContent.trim())""",
            menu,
        )
        assert covered == [], (menu, covered)
        s.page.keyboard.press("Escape")
    assert s.page.locator("#toasts .toast.error").count() >= 1  # still there, under the menu
    s.page.click("#user-button")
    s.page.click("#logout")
    s.page.wait_for_url(SIGNED_OUT)


def test_an_unread_error_outlasts_the_notices(open_session: Any, server: Server) -> None:
    """Four toasts at most: a fifth takes the place of the oldest notice, not of an error
    the student has not read yet (errors stay until closed)."""
    s: Session = open_session("carol")
    shown = s.eval(
        """async () => { const { toast } = await import('/static/js/ui.js');
           document.getElementById('toasts').replaceChildren();
           toast('The robot refused the run', {kind: 'error'});
           for (let i = 1; i <= 5; i++) toast(`Saved ${i}`, {kind: 'ok', timeout: 0});
           const titles = document.querySelectorAll('#toasts .toast strong');
           return [...titles].map((t) => t.textContent); }"""
    )
    assert shown == ["The robot refused the run", "Saved 3", "Saved 4", "Saved 5"], shown
