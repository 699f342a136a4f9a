"""Sign-out on a shared lab PC (issue 26): the copy of a workspace co-editing keeps in the
browser is removed at sign-out only once the server has every edit. Online, sign-out leaves
no copy; offline, the student is told their edit is only in this browser and chooses to
wait — the page signs out as soon as the connection is back and the edit is saved, and the
server has it."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import SIGNED_OUT, Server, Session
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(300)

KEPT = "() => Object.keys(localStorage).filter((k) => k.startsWith('melfa.coedit.'))"
STORED = "(id) => fetch(`/api/workspaces/${id}`).then((r) => r.json()).then((w) => w.program)"


def _sign_out(s: Session) -> None:
    s.page.click("#user-button")
    s.page.click("#logout")


def test_sign_out_removes_the_copy_only_once_the_server_has_it(
    open_session: Any, server: Server
) -> None:
    server.add_user("sigrid")
    online: Session = open_session("sigrid")
    ws = online.eval("() => window.melfa.workspace.id")
    online.set_program("' typed online\nEND\n")
    wait_until(lambda: online.eval(STORED, ws) == "' typed online\nEND\n", what="saved")
    assert online.eval(KEPT) == [f"melfa.coedit.sigrid.{ws}"]
    _sign_out(online)
    online.page.wait_for_url(SIGNED_OUT)
    assert online.eval(KEPT) == []  # this PC keeps no copy
    expect(online.page.locator("#signout-dialog")).to_have_count(0)  # nothing was asked

    away: Session = open_session("sigrid")
    expect(away.page.locator("#save-state")).to_contain_text("Live")
    away.context.set_offline(True)
    away.page.click("#editor")
    away.page.keyboard.press("Control+End")
    away.page.keyboard.type("' typed offline\n")
    _sign_out(away)
    dialog = away.page.locator("#signout-dialog")
    expect(dialog).to_be_visible(timeout=30_000)
    expect(dialog).to_contain_text("only in this browser")
    expect(dialog).to_contain_text("Your latest edits to My programs")  # the workspace
    away.screenshot("ide-sign-out-unsaved")
    assert away.eval(KEPT) == [f"melfa.coedit.sigrid.{ws}"]  # still kept: nothing lost
    away.page.click("#signout-wait")
    expect(dialog).to_contain_text("Waiting for the connection")  # and says so
    expect(away.page.locator("#signout-discard")).to_be_visible()  # never stuck waiting
    away.context.set_offline(False)
    away.page.wait_for_url(SIGNED_OUT, timeout=90_000)
    assert away.eval(KEPT) == []

    again: Session = open_session("sigrid")
    assert "' typed offline" in again.eval(STORED, ws)
