"""Workspaces in the IDE: nothing replaced without asking (a file opened over unsaved work
asks: open beside as a new workspace, replace, cancel), the switcher (switch, new,
rename, the group's labelled shared), switching never loses an edit, and everything acts
on the current workspace. Each test signs in a user of its own."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session

pytestmark = pytest.mark.timeout(120)

MINE = "' my own work, typed and not saved yet\nMOV P1\nEND\n"
FILE = b"10 ' the pyramid from the lab\r\n20 MOV P1\r\n30 MOV P2\r\n40 END\r\n"
FILE_TEXT = "' the pyramid from the lab\nMOV P1\nMOV P2\nEND"

STORED = "(id) => fetch(`/api/workspaces/${id}`).then((r) => r.json())"
REVISIONS = "(id) => fetch(`/api/workspaces/${id}/revisions`).then((r) => r.json())"


def _fresh(open_session: Any, server: Server, name: str, group: str | None = None) -> Session:
    server.add_user(name, group=group)
    session: Session = open_session(name)
    # The page has settled: the welcome project is in (the guide comes after it).
    session.page.wait_for_function("() => window.melfa.guide")
    return session


def _expect_menu(s: Session, names: list[str]) -> None:
    """Open the switcher's menu: it lists exactly `names` (the list may still be arriving)."""
    s.page.click("#ws-switch")
    expect(s.page.locator("#ws-menu")).to_be_visible()
    expect(s.page.locator("#ws-menu .ws-item:not(.archived) .ws-item-name")).to_have_text(names)


def test_open_beside_over_unsaved_work_makes_a_new_workspace(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    s = _fresh(open_session, server, "wsbeside")
    page = s.page
    old_id = s.eval("() => window.melfa.workspace.id")
    expect(page.locator("#ws-current-name")).to_have_text("My programs")
    s.set_program(MINE)  # unsaved: the autosave has not run yet
    assert s.eval("() => window.melfa.workspace.dirty")
    pyramid = tmp_path / "PYRAMID.MB4"
    pyramid.write_bytes(FILE)
    page.set_input_files("#file-mb4", str(pyramid))
    dialog = page.locator("#open-dialog")
    expect(dialog).to_be_visible()
    expect(dialog).to_contain_text("Open PYRAMID.MB4?")
    expect(dialog).to_contain_text("“My programs” already holds a program of 3 lines")
    expect(page.locator("#open-beside")).to_contain_text("A new workspace “PYRAMID”")
    expect(page.locator("#open-beside")).to_be_focused()  # the choice that changes nothing
    s.screenshot("open-dialog", toasts=False)
    page.click("#open-beside")

    expect(page.locator("#ws-current-name")).to_have_text("PYRAMID")
    new_id = s.eval("() => window.melfa.workspace.id")
    assert new_id != old_id
    assert s.eval("() => window.melfa.editor.text").startswith(FILE_TEXT)
    made = s.eval(STORED, new_id)
    assert (made["name"], made["program"].startswith(FILE_TEXT)) == ("PYRAMID", True)
    assert [r["reason"] for r in s.eval(REVISIONS, new_id)["revisions"]] == ["import"]
    # The old workspace kept the unsaved edit: saved before leaving, untouched since.
    assert s.eval(STORED, old_id)["program"] == MINE

    # Reachable through the switcher; switching back shows the old program.
    _expect_menu(s, ["My programs", "PYRAMID"])
    assert "null" not in s.page.inner_text("#ws-menu")
    expect(page.locator('#ws-menu [aria-checked="true"]')).to_contain_text("PYRAMID")
    s.screenshot("workspaces", toasts=False)
    page.locator("#ws-menu .ws-item", has_text="My programs").click()
    expect(page.locator("#ws-current-name")).to_have_text("My programs")
    assert s.eval("() => window.melfa.editor.text") == MINE

    # Opening the same file beside again picks a free name.
    page.set_input_files("#file-mb4", str(pyramid))
    expect(page.locator("#open-beside")).to_contain_text("“PYRAMID (2)”")
    page.click("#open-beside")
    expect(page.locator("#ws-current-name")).to_have_text("PYRAMID (2)")


def test_replace_keeps_the_old_program_as_a_revision_and_cancel_changes_nothing(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    s = _fresh(open_session, server, "wsreplace")
    page = s.page
    ws_id = s.eval("() => window.melfa.workspace.id")
    s.set_program(MINE)
    pyramid = tmp_path / "PYRAMID.MB4"
    pyramid.write_bytes(FILE)

    page.set_input_files("#file-mb4", str(pyramid))
    expect(page.locator("#open-dialog")).to_be_visible()
    page.click("#open-cancel")
    expect(page.locator("#open-dialog")).to_be_hidden()
    assert s.eval("() => window.melfa.editor.text") == MINE
    page.set_input_files("#file-mb4", str(pyramid))
    expect(page.locator("#open-dialog")).to_be_visible()
    page.keyboard.press("Escape")
    expect(page.locator("#open-dialog")).to_be_hidden()
    assert s.eval("() => window.melfa.editor.text") == MINE

    page.set_input_files("#file-mb4", str(pyramid))
    page.click("#open-replace")
    expect(page.locator(".toast", has_text="Opened PYRAMID.MB4")).to_be_visible()
    assert s.eval("() => window.melfa.editor.text").startswith(FILE_TEXT)
    assert s.eval("() => window.melfa.workspace.id") == ws_id
    expect(page.locator("#ws-current-name")).to_have_text("My programs")
    _expect_menu(s, ["My programs"])  # no workspace was made
    page.keyboard.press("Escape")
    # The program it replaced is a revision of its own (saved before the file came in,
    # by the autosave or by Replace itself, whichever came first): History shows it.
    page.wait_for_function("() => !window.melfa.workspace.dirty && !window.melfa.workspace.saving")
    numbers = [r["number"] for r in s.eval(REVISIONS, ws_id)["revisions"]]
    texts = [
        s.eval(
            "([id, n]) => fetch(`/api/workspaces/${id}/revisions/${n}`).then((r) => r.json())",
            [ws_id, n],
        )["program"]
        for n in numbers
    ]
    assert texts[0].startswith(FILE_TEXT) and MINE in texts[1:]


def test_points_file_asks_too(open_session: Any, server: Server, tmp_path: Path) -> None:
    s = _fresh(open_session, server, "wspoints")
    page = s.page
    s.set_points("DEF POS P1=(300.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n")
    other = tmp_path / "LAB.POS"
    other.write_text("DEF POS P9=(350.00,0.00,450.00,180.00,0.00,180.00)(7,0)\n")
    page.click("#tab-points")
    page.set_input_files("#file-pos", str(other))
    expect(page.locator("#open-dialog")).to_contain_text("LAB.POS replaces the points")
    page.click("#open-beside")
    expect(page.locator("#ws-current-name")).to_have_text("LAB")
    assert "P9" in s.eval("() => window.melfa.workspace.points")
    assert "P1=" not in s.eval("() => window.melfa.workspace.points")


def test_new_rename_and_a_taken_name(open_session: Any, server: Server) -> None:
    s = _fresh(open_session, server, "wsrename")
    page = s.page
    page.click("#ws-switch")
    page.click("#ws-new")
    dialog = page.locator("#ws-name-dialog")
    expect(dialog).to_be_visible()
    page.fill("#ws-name-input", "  Exam   practice ")
    page.click("#ws-name-submit")
    expect(dialog).to_be_hidden()
    expect(page.locator("#ws-current-name")).to_have_text("Exam practice")
    assert s.eval("() => window.melfa.editor.text") == ""  # a new one starts empty
    page.reload()  # … and stays empty: the welcome project is for the default one only
    s.wait_ready()
    expect(page.locator("#ws-current-name")).to_have_text("Exam practice")
    assert s.eval("() => window.melfa.editor.text") == ""

    page.click("#ws-switch")
    page.click("#ws-rename")
    expect(page.locator("#ws-name-input")).to_have_value("Exam practice")
    page.fill("#ws-name-input", "my PROGRAMS")
    page.click("#ws-name-submit")
    expect(page.locator("#ws-name-error")).to_have_text(
        "You already have a workspace called “my PROGRAMS”."
    )
    expect(page.locator("#ws-name-input")).to_have_attribute("aria-invalid", "true")
    page.fill("#ws-name-input", "")
    page.click("#ws-name-submit")
    expect(page.locator("#ws-name-error")).to_have_text("A workspace needs a name.")
    page.fill("#ws-name-input", "Final pyramid")
    page.keyboard.press("Enter")
    expect(dialog).to_be_hidden()
    expect(page.locator("#ws-current-name")).to_have_text("Final pyramid")
    _expect_menu(s, ["My programs", "Final pyramid"])
    page.keyboard.press("Escape")
    expect(page.locator("#ws-menu")).to_be_hidden()
    expect(page.locator("#ws-switch")).to_be_focused()

    # The export's file name follows the workspace's name.
    s.set_program("MOV P1\nEND\n")
    with page.expect_download() as download:
        page.click("#act-save")
    assert download.value.suggested_filename == "Final_pyramid.MB4"

    # The last opened workspace is opened again after a reload.
    page.reload()
    s.wait_ready()
    expect(page.locator("#ws-current-name")).to_have_text("Final pyramid")
    assert s.eval("() => window.melfa.editor.text") == "MOV P1\nEND\n"


def test_group_workspace_is_labelled_shared(open_session: Any, server: Server) -> None:
    s = _fresh(open_session, server, "wsgroup", group="Lab-B")
    page = s.page
    expect(page.locator("#ws-current-name")).to_have_text("Lab-B")
    expect(page.locator("#ws-shared-note")).to_have_text("shared with group Lab-B")
    expect(page.locator("#ws-switcher")).to_have_class("ws-switcher shared")
    page.click("#ws-switch")
    group_item = page.locator("#ws-menu .ws-item", has_text="Lab-B")
    expect(group_item).to_contain_text("shared with group Lab-B")
    expect(page.locator("#ws-menu .ws-item", has_text="My programs")).to_be_visible()
    s.screenshot("workspaces-shared", toasts=False)
    page.keyboard.press("Escape")


def test_switching_with_an_unsaved_edit_keeps_it(open_session: Any, server: Server) -> None:
    s = _fresh(open_session, server, "wsswitch", group="Lab-C")
    page = s.page
    group_id = s.eval("() => window.melfa.workspace.id")
    page.click("#editor")
    page.keyboard.press("Control+A")
    page.keyboard.type("' typed in the group's workspace\nEND\n")
    assert s.eval("() => window.melfa.workspace.dirty")  # the autosave has not run
    s.eval("() => window.melfa.debug.toggleBreakpoint(1)")  # kept per workspace
    page.click("#ws-switch")  # straight away
    page.locator("#ws-menu .ws-item", has_text="My programs").click()
    expect(page.locator("#ws-current-name")).to_have_text("My programs")
    typed = "' typed in the group's workspace\nEND\n"
    assert s.eval(STORED, group_id)["program"] == typed
    assert "typed in the group" not in s.eval("() => window.melfa.editor.text")
    assert s.eval("() => window.melfa.debug.breakRows") == []
    # History follows the current workspace: the group's edit is not in this one's.
    page.click("#history-button")
    expect(page.locator("#history-list")).to_be_visible()
    mine = s.eval("() => window.melfa.workspace.id")
    assert s.eval(REVISIONS, mine)["revisions"] == []
    expect(page.locator("#history-list")).to_contain_text("No revisions yet")
    page.click("#ws-switch")
    page.locator("#ws-menu .ws-item", has_text="Lab-C").click()
    expect(page.locator("#ws-current-name")).to_have_text("Lab-C")
    assert s.eval("() => window.melfa.editor.text") == typed
    assert s.eval("() => window.melfa.debug.breakRows") == [1]
    expect(page.locator("#history-list li").first).to_contain_text("wsswitch")


def test_archive_hides_a_workspace_and_brings_it_back(open_session: Any, server: Server) -> None:
    s = _fresh(open_session, server, "wsarchive")
    page = s.page
    s.eval("() => window.melfa.workspace.create('Old try', {program: 'MOV P1\\nEND\\n'})")
    expect(page.locator("#ws-current-name")).to_have_text("Old try")
    old_id = s.eval("() => window.melfa.workspace.id")
    page.click("#ws-switch")
    page.once("dialog", lambda d: d.accept())
    page.click("#ws-archive")
    expect(page.locator("#ws-current-name")).to_have_text("My programs")
    _expect_menu(s, ["My programs"])
    expect(page.locator("#ws-archive")).to_have_count(0)  # the first one stays
    page.click("#ws-show-archived")
    back = page.locator("#ws-menu .ws-item.archived", has_text="Old try")
    expect(back).to_be_visible()
    back.click()
    expect(page.locator("#ws-current-name")).to_have_text("Old try")
    assert s.eval("() => window.melfa.workspace.id") == old_id
    assert s.eval("() => window.melfa.editor.text") == "MOV P1\nEND\n"
    _expect_menu(s, ["My programs", "Old try"])
