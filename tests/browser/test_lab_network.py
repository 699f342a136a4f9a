"""Where students drive from, on the instructor's desk in Debian's Chromium at 1366×768: an
instructor lets only the lab's network (10.0.0.0/8 here, which the browser's 127.0.0.1 is
outside) drive the lab robot; a student's *Load project* is refused at once in their words,
her STOP still goes; a network that is not one is said so and nothing changes; *Allow
anywhere* lets her drive again. Screenshot for docs/ide.md."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import Page, expect

from melfa.vocab.desk import DESK_WORDS
from tests.browser.conftest import Server, Session

pytestmark = pytest.mark.timeout(300)

OUTSIDE = "The lab robot can be driven only from the lab's computers."


def _desk(s: Session) -> Page:
    page = s.page
    page.goto(s.server.url + "/desk")
    page.wait_for_selector("body[data-ready=true]")
    return page


def _csrf(s: Session) -> str:
    """The session's CSRF token (its readable cookie), for a request the page would send."""
    return next(c["value"] for c in s.context.cookies() if c["name"] == "melfa_csrf")


def test_an_instructor_keeps_the_lab_robot_to_the_lab(open_session: Any, server: Server) -> None:
    server.add_user("una", role="instructor")
    una: Session = open_session("una")
    page = _desk(una)
    alice: Session = open_session("alice")
    state = page.locator("#net-state")
    expect(state).to_contain_text("Anywhere")
    expect(page.locator("#net-you")).to_have_text("This computer: 127.0.0.1")
    expect(page.locator("#net-clear")).to_be_hidden()
    try:
        page.fill("#net-input", "192.168.10.0/33")
        page.click("#net-save")
        expect(page.locator(".toast").last).to_contain_text("'192.168.10.0/33' is not a network")
        expect(state).to_contain_text("Anywhere")  # nothing changed

        page.fill("#net-input", "10.0.0.0/8")
        page.click("#net-save")
        expect(state).to_contain_text("Only from 10.0.0.0/8")
        expect(page.locator("#net-clear")).to_be_visible()
        una.eval("() => document.querySelectorAll('.toast').forEach((t) => t.remove())")
        una.screenshot("desk-lab-network")

        alice.page.click("#act-load")  # from outside the lab: refused, in her words
        toast = alice.page.locator(".toast").last
        expect(toast).to_contain_text(OUTSIDE)
        expect(toast).to_contain_text("use My simulator")
        stop = alice.page.request.post(
            server.url + "/api/robot/stop", headers={"X-CSRF-Token": _csrf(alice)}
        )
        assert stop.ok  # STOP: from everywhere

        page.click("#net-clear")
        expect(state).to_contain_text("Anywhere")
        expect(page.locator("#net-input")).to_have_value("")
    finally:
        page.request.put(
            server.url + "/api/desk/lab-network",
            data={"networks": []},
            headers={"X-CSRF-Token": _csrf(una)},
        )
    audit = page.request.get(server.url + "/api/audit?action=lab-network.set&actor=una")
    said = [e["details"]["networks"] for e in audit.json()["entries"]]
    assert said[:3] == ["anywhere", "anywhere", "10.0.0.0/8"]  # finally, clear, set


def test_the_desk_says_when_only_part_of_its_networks_holds(
    open_session: Any, server: Server
) -> None:
    """A saved list only partly inside the server's ``--lab-network``: the card names what
    was saved beside the start-up option, and that only the part inside holds (at start),
    or will after the restart (set live), in melfa.vocab's words."""
    server.add_user("uri", role="instructor")
    page = _desk(open_session("uri"))
    saved, flag = ["10.1.0.0/16", "127.0.0.0/8"], "--lab-network 10.0.0.0/8"
    origin = {
        "source": "desk",
        "by": "ivy",
        "at": "2026-11-27T08:00:00Z",
        "command_line": flag,
        "until_restart": False,
        "cut_from": saved,
    }
    said = page.evaluate(
        """async (o) => {
          const { saidFrom } = await import("/static/js/desk.js");
          const live = { ...o, until_restart: true }, whole = { ...o, cut_from: [] };
          return [saidFrom(o), saidFrom(live), saidFrom(whole)];
        }""",
        origin,
    )
    facts = {"saved": ", ".join(saved), "flag": flag}
    keys = ("from-desk-cut", "from-desk-until-restart-cut", "from-desk")
    for text, key in zip(said, keys, strict=True):
        words = DESK_WORDS[key]
        assert text.startswith("Set by ivy on the desk, "), text
        assert text.endswith(words[words.index("{when}") + len("{when}") :].format(**facts)), text
