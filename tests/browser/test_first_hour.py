"""The student's first hour (issue 16), end to end in Debian's Chromium: plain-language
errors (a scan of every error path for wire requests, internal names and Python text),
sign-in, compressed and cached files, the keyboard, axe-core, control shared by one
user's two sessions. The layouts at 1024, 1366 and 1920 px: test_layout.py."""

from __future__ import annotations

import re
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from tests.browser.conftest import Server, Session, axe_serious, free_the_robot
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(180)

# What must never reach a student: wire requests, melfa's internal names, Python text.
LEAKS = re.compile(
    r"\d;\d;|\bRUN\d|\bJOG\d|\bEXEC[A-Z]|MSVC|SRVON|RSTALRM|Traceback|"
    r"\b[A-Z][A-Za-z]*(Error|Refused|Closed)\b|check=false|None\b|undefined|\[object"
)


def visible_texts(page: Page) -> list[str]:
    """Every error or status text a student can see now."""
    return list(
        page.evaluate(
            """() => [...document.querySelectorAll(
                '.toast, #alarm, #activity-text, #run-state, #problem-list li, #lease-text')]
              .filter((n) => n.offsetParent !== null || n.closest('.toasts'))
              .map((n) => n.innerText)"""
        )
    )


def test_sign_in_keeps_the_username_and_looks_finished(open_session: Any) -> None:
    s: Session = open_session("bob", login=False)
    page = s.page
    page.goto(s.server.url + "/login")
    assert page.evaluate("() => getComputedStyle(document.body).backgroundImage") != "none"
    page.fill("#username", "bob")
    page.fill("#password", "not the password")
    page.click("button[type=submit]")
    expect(page.locator(".error")).to_contain_text("Wrong username or password")
    expect(page.locator("#username")).to_have_value("bob")  # only the password again
    assert page.evaluate("() => document.activeElement.id") == "password"
    icon = page.context.request.get(s.server.url + "/favicon.ico")
    assert icon.ok and icon.headers["content-type"].startswith("image/svg")
    s.screenshot("login")


def test_files_are_compressed_and_cached(open_session: Any) -> None:
    s: Session = open_session("bob")
    request = s.page.context.request
    vendor = s.page.evaluate(
        "() => JSON.parse(document.querySelector('script[type=importmap]').textContent)"
        ".imports.three"
    )
    big = request.get(s.server.url + vendor.replace("three.module", "three.core"))
    assert big.headers.get("content-encoding") == "gzip"
    assert "immutable" in big.headers["cache-control"]
    own = request.get(s.server.url + "/static/js/main.js")
    assert own.headers["cache-control"] == "no-cache" and own.headers.get("etag")
    again = request.get(
        s.server.url + "/static/js/main.js", headers={"If-None-Match": own.headers["etag"]}
    )
    assert again.status == 304


def test_error_scan_every_path_speaks_plainly(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    """Drive the error paths a student meets; no text on the page may leak."""
    s: Session = open_session("alice")
    page = s.page
    free_the_robot(page, server)
    seen: list[str] = []

    def collect() -> None:
        page.wait_for_timeout(300)
        seen.extend(visible_texts(page))
        page.evaluate("() => document.querySelectorAll('.toast').forEach((t) => t.remove())")

    s.set_points("DEF POS P1=(400.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n")
    s.set_program("MOV P1\nMOV PINIC\nEND\n")
    # 1. The servo is off: Go to, Run, jog.
    page.click("#tab-robot")
    page.select_option("#goto-point", "P1")
    page.click("#goto-move")
    expect(page.locator(".toast.error", has_text="servo is off")).to_be_visible()
    collect()
    page.locator("#jog-canvas").focus()
    page.keyboard.down("w")
    expect(page.locator(".toast.error", has_text="Could not jog")).to_be_visible()
    page.keyboard.up("w")
    collect()
    # 2. Run before anything is loaded in this session (the program slot may be empty).
    page.click("#act-run")
    page.click("#run-anyway")  # Run asks first: the slot does not hold her text
    expect(page.locator(".toast.error")).to_be_visible()
    collect()
    # 3. An undefined point: the problems list offers to add it from the current position.
    page.click("#tab-editor")
    page.click("#act-check")
    fix = page.get_by_role("button", name="Add PINIC from the current position")
    expect(fix).to_be_visible()
    collect()
    fix.click()
    wait_until(lambda: "PINIC=" in s.eval("() => window.melfa.workspace.points"), what="PINIC")
    # 4. A program with an error is refused before it is sent.
    s.set_program("MOV P1\nWIHLE 1\nEND\n")
    page.click("#act-load")
    expect(page.locator(".toast.error", has_text="Not loaded")).to_be_visible()
    collect()
    # 5. Someone else holds control.
    free_the_robot(page, server)
    bob: Session = open_session("bob")
    bob.page.click("#lease-take")
    expect(page.locator("#lease-text")).to_contain_text("bob")
    page.click("#tab-robot")
    page.click("#servo-on")
    expect(page.locator(".toast.error")).to_be_visible()
    collect()
    bob.page.click("#lease-release")
    # 6. An alarm: the controller refuses a move (joint limit) and the alarm says what to do.
    s.eval("() => window.melfa.workspace.update({points: 'DEF JNT JFAR=(500,0,90,0,90,0)\\n'})")
    page.select_option("#goto-point", "JFAR")
    page.click("#goto-move")
    toast = page.locator(".toast.error").first
    expect(toast).to_be_visible()
    if toast.get_by_role("button", name="Turn on and retry").count():
        toast.get_by_role("button", name="Turn on and retry").click()
    page.wait_for_timeout(1500)
    collect()
    # The session's robot log lists what was asked and what came of it, in words.
    page.click("#action-log-button")
    log = page.locator("#action-log")
    expect(log).to_contain_text("Move to")
    expect(log).to_contain_text("servo is off")
    seen.append(log.inner_text())
    s.screenshot("robot-log")
    log.get_by_role("button", name="Close").click()
    free_the_robot(page, server)  # the joint-limit alarm must not block later tests
    leaks = [t for t in seen if LEAKS.search(t)]
    assert not leaks, leaks
    assert any("L2000" in t for t in seen), seen  # the controller's code stays visible


def test_keyboard_only_leaves_the_editor_and_reaches_every_control(open_session: Any) -> None:
    s: Session = open_session("carol")
    page = s.page
    expect(page.locator("#editor-hint")).to_contain_text("Esc")
    page.click("#editor")
    # Ace's mousedown queues a task that focuses the editor again if it lost focus; a busy
    # renderer runs key presses before it, so Esc, Tab would leave and that task come back.
    # A student's keys come after it: wait for it as they do (a task queued now runs after).
    s.eval("() => new Promise((done) => setTimeout(done))")
    page.keyboard.press("Tab")  # indents inside the editor
    assert s.eval("() => !!document.activeElement.closest('#editor')")
    page.keyboard.press("Escape")
    page.keyboard.press("Tab")
    assert not s.eval("() => !!document.activeElement.closest('#editor')")
    # Tabbing on reaches the jog pad's tab, the problems, the 3D view's buttons; focus shows.
    reached: set[str] = set()
    for _ in range(90):
        if s.eval("() => !!document.activeElement.closest('#editor')"):
            page.keyboard.press("Escape")  # the way out, as the hint says
        page.keyboard.press("Tab")
        info = s.eval(
            """() => { const a = document.activeElement;
                 if (a === document.body) return ['(page)', true];  // past the last control
                 const st = getComputedStyle(a);
                 return [a.id || a.getAttribute('aria-label') || a.textContent.trim().slice(0, 20),
                         st.outlineStyle !== 'none' || st.boxShadow !== 'none']; }"""
        )
        reached.add(info[0])
        assert info[1], f"no visible focus on {info[0]}"
    for control in ("act-load", "act-run", "estop", "path-clear", "view-reset", "tab-editor"):
        assert control in reached, (control, sorted(reached))


def test_axe_finds_no_serious_problem(open_session: Any) -> None:
    s: Session = open_session("carol")
    page = s.page
    found = []
    for tab in ("editor", "points", "robot"):
        page.click(f"#tab-{tab}")
        found += [f"{tab}: {problem}" for problem in axe_serious(page)]
    assert not found, "\n".join(found)


def test_one_user_two_sessions_share_control(open_session: Any, server: Server) -> None:
    if "dana" not in server.passwords:
        server.add_user("dana")
    first: Session = open_session("dana")
    free_the_robot(first.page, server)
    second: Session = open_session("dana")
    first.page.click("#lease-take")
    expect(first.page.locator("#lease-text")).to_contain_text("you")
    expect(second.page.locator("#lease-text")).to_contain_text("you")  # the same user
    expect(second.page.locator("#lease-text")).to_contain_text("since")
    # The second tab may act without being refused "dana holds the robot".
    second.page.click("#tab-robot")
    second.page.click("#servo-on")
    wait_until(lambda: second.eval("() => window.melfa.state.servo") is True, what="servo on")
    assert not second.page.locator(".toast.error").count()
    second.page.click("#lease-release")
    expect(first.page.locator("#lease-text")).to_contain_text("free")
