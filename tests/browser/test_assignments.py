"""Assignments in Debian's Chromium (issue 23's "Done when"): an instructor publishes an
assignment with variants from its zipped folder; two students open it and get different
positions, check, fail on the right line (a click goes there), fix, pass and submit; the
class view shows both; its CSV export; a student's work opened read-only with its history
and diff. Screenshots for docs/ide.md at 1366×768."""

from __future__ import annotations

import csv
import io
import zipfile
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from tests.browser.conftest import Server, Session, axe_serious

pytestmark = pytest.mark.timeout(180)

FOLDER = Path(__file__).resolve().parents[1] / "web" / "assignments" / "place-block"
FIX = "MVS P1, 50\nEND"
GRADING = 60_000  # ms: a hang guard for a grading on a loaded shared machine (bench/ measures it)


def _zip(tmp_path: Path) -> Path:
    path = tmp_path / "reach-the-block.zip"
    with zipfile.ZipFile(path, "w") as z:
        for f in sorted(FOLDER.iterdir()):
            z.write(f, f"reach-the-block/{f.name}")
    return path


def _axe_mine(page: Page) -> list[str]:
    """axe-core's serious findings in what this change draws (the assignment's pane and
    list, the class view page); the rest of the IDE has its own tests."""
    return [p for p in axe_serious(page) if any(k in p for k in ("assign", "cv-", "pub-"))]


def _student_works(s: Session, title: str) -> str:
    """Open the assignment, check (fails on line 3: a click there moves the cursor), fix,
    check (passes), submit. Returns the student's points (their variant)."""
    page = s.page
    page.click("#assign-open")
    dialog = page.locator("#assign-dialog")
    expect(dialog).to_be_visible()
    dialog.locator(".assign-row", has_text=title).get_by_role("button").click()
    expect(page.locator("#ws-current-name")).to_have_text(title)
    expect(page.locator("#target-switch [data-target=mine]")).to_have_attribute(
        "aria-checked", "true"
    )
    pane = page.locator("#assignment")
    expect(pane).to_be_visible()
    expect(page.locator("#assign-statement")).to_contain_text("50 mm below")
    expect(page.locator("#assign-variant")).to_contain_text("pick: X +0, Y")
    points = str(s.eval("() => window.melfa.workspace.points"))
    assert "P1=(400.00," in points

    page.click("#assign-check")
    failed = page.locator("#assign-checks li.fail")
    expect(failed).to_have_count(1, timeout=GRADING)
    expect(failed).to_contain_text("50.0 mm from")
    expect(page.locator("#assign-checks li.pass")).to_have_count(2)
    expect(page.locator("#assign-summary")).to_have_attribute("data-passed", "false")
    expect(page.locator("#assign-summary")).to_have_text("Checked: 2 of 3 checks passed.")
    failed.locator("button.line").click()
    assert s.eval("() => window.melfa.editor.editor.getCursorPosition().row") == 2  # line 3
    if s.user == "alice":
        s.screenshot("assignment-check-failed", toasts=False)

    s.set_program(str(s.eval("() => window.melfa.editor.text")).replace("END", FIX))
    page.click("#assign-check")
    expect(page.locator("#assign-summary")).to_have_attribute(
        "data-passed", "true", timeout=GRADING
    )
    expect(page.locator("#assign-checks li.pass")).to_have_count(3)
    page.click("#assign-submit")
    # The toast names the revision graded: 2 or more (an autosave may record the fix on its
    # own first on a loaded machine).
    s.saw_toast(r"Revision [2-9] is recorded", timeout=GRADING)
    expect(page.locator("#assign-attempts")).to_have_text(
        "2 of 3 submissions left", timeout=GRADING
    )
    # What was graded, in words that never read as a failed submission ("Submit: failed")
    expect(page.locator("#assign-summary")).to_have_text("Submitted: every check passed.")
    if s.user == "alice":
        s.screenshot("assignment-passed", toasts=False)
        assert _axe_mine(page) == []
    return points


def test_publish_work_submit_and_the_class_view(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    server.add_user("teach", role="instructor")
    teacher: Session = open_session("teach")
    page = teacher.open_page("/classroom")
    page.click("#cv-publish")
    expect(page.locator("#publish-dialog")).to_be_visible()
    page.set_input_files("#pub-zip", str(_zip(tmp_path)))
    expect(page.locator("#pub-title")).to_have_text("Reach the block")
    expect(page.locator("#pub-variants")).to_be_checked()
    expect(page.locator("#pub-attempts")).to_have_value("3")
    teacher.screenshot("classroom-publish", toasts=False)
    assert _axe_mine(page) == []
    page.click("#pub-ok")
    expect(page.locator("#publish-dialog")).to_be_hidden()
    expect(page.locator("#cv-title")).to_have_text("Reach the block")
    expect(page.locator("#cv-rows tr[data-student=alice]")).to_contain_text("not opened")

    alice: Session = open_session("alice")
    bob: Session = open_session("bob")
    alice_points = _student_works(alice, "Reach the block")
    bob_points = _student_works(bob, "Reach the block")
    assert alice_points != bob_points  # two students, two places to reach

    page.reload()
    page.wait_for_selector("body[data-ready=true]")
    for name in ("alice", "bob"):
        row = page.locator(f"#cv-rows tr[data-student={name}]")
        expect(row.locator("[data-column=best]")).to_have_text("every check passed")
        expect(row.locator("[data-column=latest]")).to_have_text("every check passed")
        expect(row.locator("[data-column=preflight]")).to_have_text("passed")
        expect(row.locator("[data-column=attempts]")).to_have_text("1 (2 left)")
        expect(row.locator("[data-column=ran]")).to_have_text("—")  # nobody used the arm
    page.select_option("#cv-filter", "passed")
    expect(page.locator("#cv-rows tr")).to_have_count(2)
    page.select_option("#cv-filter", "all")
    expect(page.locator("#cv-rows tr[data-student=carol]")).to_contain_text("not opened")

    with page.expect_download() as download:
        page.click("#cv-csv")
    table = list(csv.reader(io.StringIO(Path(download.value.path()).read_text())))
    rows = {r[0]: r for r in table[1:]}
    assert table[0][:4] == ["Student", "Group", "Variant", "Latest check"]
    assert rows["alice"][4] == rows["bob"][4] == "every check passed"
    assert rows["alice"][2] != rows["bob"][2]  # their variants

    page.locator("#cv-rows tr[data-student=alice]").get_by_role("button").click()
    drawer = page.locator("#cv-student")
    expect(drawer).to_be_visible()
    expect(page.locator("#cv-revisions li")).to_have_count(2)
    expect(page.locator("#cv-program .add")).to_have_text("  4 + MVS P1, 50\n")
    expect(page.locator("#cv-gradings li")).to_have_count(3)
    page.locator("#cv-gradings button").last.click()  # the first check: it failed
    expect(page.locator("#cv-report li.fail")).to_contain_text("line 3")
    expect(page.locator("#cv-diff-note")).to_have_text("Revision 1, the first.")
    expect(page.locator("#cv-program .add")).to_have_count(0)
    teacher.screenshot("classroom-class-view", toasts=False)
    assert _axe_mine(page) == []
