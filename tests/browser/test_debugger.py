"""A student's own simulator and its debugger, in the browser: with the lab robot held by
someone else, a student still runs and debugs on "My simulator" (breakpoint in the gutter,
step, step over, step out, variables changing, an input releasing a WAIT, run to cursor, a
run-time error stopping on its line, the current line kept across a reload)."""

from __future__ import annotations

import re
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from tests.browser.conftest import Session

pytestmark = pytest.mark.timeout(180)

PROGRAM = """SERVO ON
M1 = 1
GOSUB *SUB
M1 = M1 + 1
WAIT M_IN(8) = 1
MOV P1
M2 = M1 * 10
END
*SUB
M3 = 5
RETURN
"""
POINTS = "DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
LOOP = "SERVO ON\n*LOOP\nMOV P1\nMOV P2\nGOTO *LOOP\n"
LOOP_POINTS = POINTS + "DEF POS P2=(300.00,200.00,400.00,180.00,0.00,180.00)(7,0)\n"


def to_mine(s: Session) -> None:
    s.page.click("#target-switch [data-target=mine]")
    expect(s.page.locator("body")).to_have_attribute("data-target", "mine")
    s.page.wait_for_function("() => window.melfa.state && window.melfa.state.joints")


def at_line(page: Page, line: int, state: str = "paused") -> None:
    expect(page.locator("#dbg-status")).to_have_attribute("data-state", state)
    expect(page.locator("#dbg-status")).to_have_attribute("data-line", str(line))
    expect(page.locator("#editor")).to_have_attribute("data-debug-line", str(line))


def gutter(page: Page, line: int) -> None:
    """Click the gutter of ``line`` (a breakpoint on, or off), as a student would: with the
    line in view and the editor still (a stop scrolls it, animated, to the stopped line: a
    click measured mid-scroll lands on another row), then see that this line toggled."""
    editor = "window.melfa.editor.editor"
    page.wait_for_function(f"() => !{editor}.renderer.$scrollAnimation")
    page.evaluate(f"(n) => {editor}.scrollToLine(n - 1, true, false, () => {{}})", line)
    page.evaluate("() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))")
    before = page.evaluate(f"(n) => !!{editor}.session.getBreakpoints()[n - 1]", line)
    cell = page.locator(".ace_gutter-cell").filter(has_text=re.compile(rf"^\s*{line}\s*$"))
    box = cell.first.bounding_box()
    assert box is not None
    page.mouse.click(box["x"] + 6, box["y"] + box["height"] / 2)
    page.wait_for_function(
        f"([n, was]) => !!{editor}.session.getBreakpoints()[n - 1] !== was", arg=[line, before]
    )


def variable(page: Page, name: str) -> Any:
    return page.locator(f"#dbg-vars tr[data-name='{name}']")


def test_a_student_runs_and_debugs_on_their_simulator_while_the_lab_is_held(
    open_session: Any,
) -> None:
    holder: Session = open_session("bob")
    holder.page.click("#lease-take")
    expect(holder.page.locator("#lease-text")).to_contain_text("you")

    s: Session = open_session("carol")
    page = s.page
    expect(page.locator("#lease-text")).to_contain_text("bob")
    to_mine(s)
    expect(page.locator(".lease")).to_be_hidden()  # no lease on one's own simulator
    expect(page.locator(".view-head h2")).to_have_text("My simulator")

    # Load and run on the simulator: nobody's lease is in the way.
    s.set_program(LOOP)
    s.set_points(LOOP_POINTS)
    page.click("#act-load")
    expect(page.locator(".toast", has_text="Project loaded")).to_be_visible()
    # My simulator loads at once: the activity line says so, not "Project loaded in 0.0 s".
    expect(page.locator("#activity-text")).not_to_contain_text("0.0 s")
    said = s.eval(
        "async () => { const { took } = await import('/static/js/ui.js');"
        " return [0, 0.04, 0.1, 0.4242, 1.26, 12.3].map((t) => took('Project loaded', t)); }"
    )
    assert said == [
        "Project loaded",
        "Project loaded",
        "Project loaded in 0.1 s",
        "Project loaded in 0.42 s",
        "Project loaded in 1.3 s",
        "Project loaded in 12 s",
    ]
    page.click("#tab-robot")
    page.click("#servo-on")
    expect(page.locator("#servo-state")).to_have_text("on")
    page.click("#tab-editor")
    page.click("#act-run")
    page.wait_for_function("() => window.melfa.state && window.melfa.state.running === true")
    page.click("#act-stop")
    page.wait_for_function("() => window.melfa.state && window.melfa.state.running === false")

    # The debugger: a breakpoint in the gutter, then step, step out, step over.
    s.set_program(PROGRAM)
    s.set_points(POINTS)
    gutter(page, 3)
    expect(page.locator(".ace_gutter-cell.melfa-breakpoint")).to_have_count(1)
    page.select_option("#dbg-speed", "instant")
    page.click("#dbg-start")
    at_line(page, 3)
    expect(page.locator("#dbg-status")).to_contain_text("breakpoint")
    expect(variable(page, "M1")).to_contain_text("1")
    page.click("#dbg-step")  # into the GOSUB: its label line
    at_line(page, 9)
    page.click("#dbg-step")
    at_line(page, 10)
    page.click("#dbg-step")
    at_line(page, 11)
    expect(variable(page, "M3")).to_have_class(re.compile("changed"))
    expect(variable(page, "M3")).to_contain_text("5")
    page.click("#dbg-out")
    at_line(page, 4)
    page.click("#dbg-next")
    at_line(page, 5)
    expect(variable(page, "M1")).to_have_class(re.compile("changed"))
    expect(variable(page, "M1").locator("td")).to_have_text("2")
    expect(variable(page, "M3")).not_to_have_class(re.compile("changed"))

    # The current line survives a reload: the server holds the session.
    page.reload()
    s.wait_ready()
    at_line(page, 5)
    expect(page.locator("body")).to_have_attribute("data-target", "mine")

    # A WAIT on an input: the panel offers to set it, and the program goes on.
    page.click("#dbg-continue")
    expect(page.locator("#dbg-wait")).to_contain_text("WAIT M_IN(8)")
    # The offer stays the same button while the waiting program's status keeps arriving, so a
    # press and its release land on one element (a rebuilt button never gets the click).
    page.evaluate("() => { window.__release = document.getElementById('dbg-release'); }")
    first = page.locator("#dbg-status").text_content()
    page.wait_for_function(
        "(t) => document.getElementById('dbg-status').textContent !== t", arg=first
    )
    assert page.evaluate("() => document.getElementById('dbg-release') === window.__release")
    page.click("#dbg-release")
    expect(page.locator("#dbg-status")).to_have_attribute("data-state", "finished")
    expect(variable(page, "M2").locator("td")).to_have_text("20")
    s.screenshot("debugger")

    # Run to cursor: no breakpoint, the cursor on line 7.
    gutter(page, 3)
    expect(page.locator(".ace_gutter-cell.melfa-breakpoint")).to_have_count(0)
    s.eval("() => window.melfa.editor.editor.gotoLine(7, 0, false)")
    page.click("#dbg-cursor")  # from the start again; M_IN(8) is still 1: no wait
    at_line(page, 7)
    holder.page.click("#lease-release")


def test_a_run_time_error_stops_on_its_line_with_the_controllers_number(
    open_session: Any,
) -> None:
    s: Session = open_session("alice")
    page = s.page
    to_mine(s)
    s.set_program("SERVO ON\nM1 = 1\nM2 = M9 + 1\nEND\n")
    s.set_points("")
    page.select_option("#dbg-speed", "instant")
    page.click("#dbg-start")
    error = page.locator("#dbg-error")
    expect(error).to_be_visible()
    expect(error).to_have_attribute("data-line", "3")
    expect(error).to_contain_text("at line 3")
    expect(error).to_contain_text(re.compile(r"Error L\d{4}"))
    expect(error).to_contain_text("M9")
    expect(page.locator(".ace_marker-layer .melfa-debug-error")).to_have_count(1)
    at_line(page, 3, state="failed")
    s.screenshot("debugger-error")
    # Back on the lab robot the debugger is out of the way.
    page.click("#target-switch [data-target=lab]")
    expect(page.locator("#debug-bar")).to_be_hidden()
    expect(page.locator(".lease")).to_be_visible()


def test_a_run_starts_as_the_start_options_say(open_session: Any) -> None:
    """The servo on, the arm at a position in XYZ, a line for INPUT #1 and the override,
    chosen in "How the run starts": a program that begins with a motion and reads a file
    runs to its end; a position out of reach is refused in words."""
    s: Session = open_session("alice")
    page = s.page
    to_mine(s)
    s.set_program('OPEN "COM1:" AS #1\nINPUT #1, M1\nM2 = M1 * 2\nMOV P1\nEND\n')
    s.set_points(POINTS)
    page.click("#start-opts summary")
    expect(page.locator("#start-opts summary")).to_have_text("How the run starts")
    expect(page.locator("#start-pose")).to_be_hidden()
    page.select_option("#start-servo", "on")
    page.select_option("#start-place", "pose")
    expect(page.locator("#start-pose")).to_be_visible()
    expect(page.locator("#start-joints")).to_be_hidden()
    for axis, value in zip(range(3), ("300", "100", "500"), strict=True):
        page.fill(f"#start-p-{axis}", value)
    page.fill("#start-override", "40")
    page.click("#start-feed-add")
    page.locator(".start-feed-line").fill("21")
    page.locator(".start-feed-line").press("Tab")  # the change is kept
    expect(page.locator("#start-opts")).to_have_attribute("data-custom", "true")
    page.select_option("#dbg-speed", "instant")
    page.click("#dbg-start")
    expect(page.locator("#dbg-status")).to_have_attribute("data-state", "finished")
    expect(variable(page, "M2").locator("td")).to_have_text("42")
    s.screenshot("debugger-start-options")

    # Kept in this browser; a position the arm cannot take is refused in words.
    page.reload()
    s.wait_ready()
    expect(page.locator("#start-place")).to_have_value("pose")
    expect(page.locator("#start-p-0")).to_have_value("300")
    page.click("#start-opts summary")
    page.fill("#start-p-0", "2000")
    page.locator("#start-p-0").press("Tab")
    page.click("#dbg-start")
    expect(page.locator(".toast").last).to_contain_text("out of the RV-6S's reach")
    s.screenshot("debugger-start-unreachable")


def test_my_simulator_never_says_you_took_control_of_the_robot(open_session: Any) -> None:
    """My simulator is the student's alone: switching its servo on said "You have control of
    the robot … Others can watch; press Release when you are done", with no Release to
    press and nobody watching. The lab robot still says it."""
    s: Session = open_session("carol")
    page = s.page
    failed: list[str] = []  # nothing being debugged is no error: no 404 in the console
    page.on("response", lambda r: failed.append(r.url) if r.status >= 400 else None)
    with page.expect_response(lambda r: r.url.endswith("/api/debug")):
        page.click("#target-switch [data-target=mine]")
    s.wait_ready()
    assert failed == []
    page.click("#tab-robot")
    s.eval("() => { window.leases = []; window.melfa.live.on('lease', (m) => leases.push(m)); }")
    page.click("#servo-on")
    expect(page.locator("#servo-state")).to_have_text("on")
    # The simulator's own control went to her with that command: once its message has come
    # (the page's toasts are made in the handler before ours), no toast came with it
    page.wait_for_function("() => window.leases.some((m) => m.command)")
    assert "You have control" not in page.inner_text("#toasts")
    page.click("#servo-off")
    expect(page.locator("#servo-state")).to_have_text("off")
    page.click("#target-switch [data-target=lab]")


def test_a_breakpoint_removed_just_before_continue_is_gone(open_session: Any) -> None:
    """The gutter's PUT and *Continue*'s POST travel on two connections: the POST waits for
    the PUT, or the run stops at the breakpoint the student has just taken away. The test
    holds the PUT in the browser and sees whether *Continue* goes out before it."""
    s: Session = open_session("carol")
    page = s.page
    to_mine(s)
    s.set_program("M1 = 1\nM1 = 2\nM1 = 3\nM1 = 4\nEND\n")
    s.set_points("")
    gutter(page, 2)
    gutter(page, 4)
    expect(page.locator(".ace_gutter-cell.melfa-breakpoint")).to_have_count(2)
    page.select_option("#dbg-speed", "instant")
    page.click("#dbg-start")
    at_line(page, 2)

    held: list[Any] = []
    continued_while_held: list[bool] = []
    page.route("**/api/debug/breakpoints", lambda route: held.append(route))
    page.route(
        "**/api/debug/command/continue",
        lambda route: (continued_while_held.append(bool(held)), route.continue_()),
    )
    gutter(page, 4)  # off again, while the run stands at line 2
    page.wait_for_function("() => true")  # the PUT is out (and held)
    assert len(held) == 1
    page.click("#dbg-continue")
    page.wait_for_function("() => true")  # a POST sent on the click is routed by now
    held.pop().continue_()
    expect(page.locator("#dbg-status")).to_have_attribute("data-state", "finished")
    assert continued_while_held == [False]
