"""An instructor opens a student's workspace (issue 26, the instructor's desk) in Debian's
Chromium: it is read-only, under a banner saying whose work it is; nothing typed reaches
the student's work and the server refuses a save sent anyway; *Edit as instructor* (audited)
lets them type, the student's work gets the line, and *Back to read-only* ends it."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session

pytestmark = pytest.mark.timeout(300)


def _csrf(s: Session) -> str:
    return str(s.eval("() => document.cookie.match(/melfa_csrf=([^;]+)/)[1]"))


def _program(s: Session, ws: int) -> str:
    return str(s.page.request.get(f"{s.server.url}/api/workspaces/{ws}").json()["program"])


def test_an_instructor_reads_a_student_s_work_until_they_choose_to_edit(
    open_session: Any, server: Server
) -> None:
    server.add_user("rosa")
    server.add_user("quinn", role="instructor")
    rosa: Session = open_session("rosa")
    rosa.set_program("MOV P1\nEND\n")
    rosa.eval("() => window.melfa.workspace.save('save')")
    ws = int(rosa.eval("() => window.melfa.workspace.id"))
    rosa.page.wait_for_function("() => window.melfa.workspace.base > 0")

    quinn: Session = open_session("quinn", login=False)
    quinn.login_api()
    quinn.page.goto(f"{server.url}/desk")  # the desk's Open work: the same read-only view
    quinn.page.wait_for_selector("body[data-ready=true]")
    with quinn.context.expect_page() as opened:
        quinn.page.click("#acc-rows tr[data-user=rosa] [data-act=work]")
    desk = quinn.page
    quinn.page = opened.value
    quinn.wait_ready()
    assert quinn.eval("() => window.melfa.workspace.id") == ws
    quinn.page.close()
    quinn.page = desk
    quinn.page.goto(f"{server.url}/?workspace={ws}")  # as the class view's link opens it
    quinn.wait_ready()
    banner = quinn.page.locator("#visit-banner")
    expect(banner).to_be_visible()
    expect(banner).to_contain_text("You are reading rosa's work")
    expect(banner).to_contain_text("read-only")
    assert quinn.eval("() => window.melfa.editor.editor.getReadOnly()") is True
    quinn.page.click("#editor .ace_content")
    quinn.page.keyboard.type("' the instructor's note\n")
    assert _program(quinn, ws) == "MOV P1\nEND\n"
    quinn.screenshot("staff-reading")

    # The server decides, not the page: a save sent anyway is refused.
    sent = quinn.page.request.put(
        f"{server.url}/api/workspaces/{ws}",
        data={"base": 1, "program": "' sent anyway\n", "points": ""},
        headers={"X-CSRF-Token": _csrf(quinn)},
    )
    assert sent.status == 403 and sent.json()["error"]["code"] == "read-only"
    assert _program(rosa, ws) == "MOV P1\nEND\n"

    quinn.page.click("#visit-edit")  # Edit as instructor
    expect(banner).to_contain_text("You are editing rosa's work")
    quinn.page.wait_for_function("() => !window.melfa.editor.editor.getReadOnly()")
    quinn.eval("() => window.melfa.editor.editor.navigateFileStart()")
    quinn.page.click("#editor .ace_content")
    quinn.eval("() => window.melfa.editor.editor.navigateFileStart()")
    quinn.page.keyboard.type("' checked by quinn\n")
    rosa.page.wait_for_function(
        '() => window.melfa.workspace.program.startsWith("\' checked by quinn")'
    )
    quinn.eval("() => window.melfa.workspace.save('save')")
    quinn.page.wait_for_function(
        "async (ws) => (await (await fetch(`/api/workspaces/${ws}`)).json()).program"
        '.startsWith("\' checked by quinn")',
        arg=ws,
    )
    quinn.screenshot("staff-editing")
    entries = quinn.page.request.get(f"{server.url}/api/audit?actor=quinn").json()["entries"]
    edit = [e for e in entries if e["action"] == "workspace.edit-as-staff"]
    assert len(edit) == 1 and edit[0]["details"]["who"] == "rosa"

    quinn.page.click("#visit-edit")  # Back to read-only
    expect(banner).to_contain_text("You are reading rosa's work")
    quinn.page.wait_for_function("() => window.melfa.editor.editor.getReadOnly()")
