"""Two students of one group in one workspace, in two Chromium pages against a real
`melfa serve` (issue 26's three rounds of lost lines): both type at once and both lines
survive on both screens and on the server, each sees the other here and where their
cursor is, and one of them offline for 30 s keeps typing, then reconnects: everything
typed on both sides is on both screens and on the server. No dialog asks anything."""

from __future__ import annotations

import time
from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(240)

STORED = "(id) => fetch(`/api/workspaces/${id}`).then((r) => r.json()).then((w) => w.program)"
OFFLINE_S = 30.0
"""How long the second student is offline: longer than the server's silence limit (15 s),
so the socket is really gone and the server has dropped them from presence."""

# Type `text` into this page's editor one character every 30 ms, the way keystrokes come,
# without waiting: the two pages type at the same time.
TYPE_LATER = """([text, where]) => {
  const ed = window.melfa.editor.editor;
  if (where === "start") ed.gotoLine(1, 0); else ed.navigateFileEnd();
  window.typed = false;
  let i = 0;
  const timer = setInterval(() => {
    ed.insert(text[i++]);
    if (i >= text.length) { clearInterval(timer); window.typed = true; }
  }, 30);
}"""


def _text(s: Session) -> str:
    return str(s.eval("() => window.melfa.editor.text"))


def _pair(open_session: Any, server: Server) -> tuple[Session, Session]:
    for name in ("pair1a", "pair1b"):
        if name not in server.passwords:
            server.add_user(name, group="Pair-1")
    first: Session = open_session("pair1a")
    second: Session = open_session("pair1b")
    for s in (first, second):
        s.page.wait_for_function("() => window.melfa.guide")  # the page has settled
    return first, second


def test_two_partners_typing_at_once_and_one_offline_lose_nothing(
    open_session: Any, server: Server
) -> None:
    alice, bob = _pair(open_session, server)
    ws = alice.eval("() => window.melfa.workspace.id")
    assert bob.eval("() => window.melfa.workspace.id") == ws  # the group's workspace
    alice.set_program("MOV P1\nEND\n")
    wait_until(lambda: _text(bob) == "MOV P1\nEND\n", what=lambda: _text(bob))

    # Presence: each sees the other, named, and the other's cursor in the editor.
    expect(alice.page.locator("#presence")).to_contain_text("pair1b")
    expect(bob.page.locator("#presence")).to_contain_text("pair1a")
    bob.page.click("#editor")
    bob.eval("() => window.melfa.editor.editor.gotoLine(2, 0)")
    expect(alice.page.locator(".peer-cursor[data-user=pair1b]")).to_have_attribute("data-line", "2")

    # Both type at once, on two lines.
    alice.eval(TYPE_LATER, ["' alice types here\n", "start"])
    bob.eval(TYPE_LATER, ["' bob types there\n", "end"])
    for s in (alice, bob):
        s.page.wait_for_function("() => window.typed")
    both = "' alice types here\nMOV P1\nEND\n' bob types there\n"
    for s in (alice, bob):
        wait_until(lambda s=s: _text(s) == both, what=lambda s=s: f"{s.user}: {_text(s)!r}")
    wait_until(lambda: alice.eval(STORED, ws) == both, what="the server's revision")
    # bob's cursor moves: alice sees it on its new line, with his name.
    bob.eval("() => window.melfa.editor.editor.gotoLine(4, 5)")
    cursor = alice.page.locator(".peer-cursor[data-user=pair1b]:not(.quiet)")
    expect(cursor).to_have_attribute("data-line", "4")
    alice.screenshot("ide-coedit", toasts=False)

    # bob goes offline for 30 s and keeps typing; alice types meanwhile.
    went = time.monotonic()
    bob.context.set_offline(True)
    bob.page.click("#editor")
    bob.page.keyboard.press("Control+End")
    bob.page.keyboard.type("' bob, offline\n")
    alice.page.click("#editor")
    alice.page.keyboard.press("Control+Home")
    alice.page.keyboard.type("' alice, while bob is away\n")
    expect(bob.page.locator("#save-state")).to_contain_text("Offline", timeout=20_000)
    expect(alice.page.locator("#presence")).not_to_contain_text("pair1b", timeout=25_000)
    left = OFFLINE_S - (time.monotonic() - went)
    if left > 0:
        bob.page.wait_for_timeout(left * 1000)  # the scenario's 30 s, not a measurement
    bob.context.set_offline(False)

    everything = (
        "' alice, while bob is away\n' alice types here\nMOV P1\nEND\n"
        "' bob types there\n' bob, offline\n"
    )
    for s in (alice, bob):
        wait_until(lambda s=s: _text(s) == everything, 40, lambda s=s: f"{s.user}: {_text(s)!r}")
    wait_until(lambda: alice.eval(STORED, ws) == everything, 20, "the server's revision")
    expect(alice.page.locator("#presence")).to_contain_text("pair1b", timeout=20_000)
    expect(bob.page.locator("#save-state")).to_contain_text("Saved")
    # No dialog was ever shown.
    for s in (alice, bob):
        assert s.eval("() => [...document.querySelectorAll('dialog')].every((d) => !d.open)")
    history = alice.eval(
        "(id) => fetch(`/api/workspaces/${id}/revisions`).then((r) => r.json())", ws
    )["revisions"]
    assert any("pair1b" in (r["author"] or "") for r in history)
