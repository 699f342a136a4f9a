"""Program text shown read-only keeps every line whole (Debian's Chromium at 1366×768): an
instructor reading a student's solution in the class view's side panel sees a long comment
line to its end, wrapped under its own text with the line numbers still in their column;
the same student's work opened read-only in the editor (the desk's and the class view's
*Open in the editor*) wraps its long lines instead of scrolling sideways; a recorded run's
replay names its running line whole."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session, free_the_robot
from tests.browser.test_replay import recorded_run

pytestmark = pytest.mark.timeout(240)

FOLDER = Path(__file__).resolve().parents[1] / "web" / "assignments" / "place-block"
LONG = (  # 111 characters: a step the controller takes (127 at most), wider than the panel
    "' Approach from above: clear the fixture's left wall by 40 mm, "
    "hand open until the block is level with the jaws"
)
COMMENT = (
    "' above the block: clear the fixture's left wall by 40 mm, the hand open until the jaws "
    "are level"
)


def _csrf(s: Session) -> str:
    return str(s.eval("() => document.cookie.match(/melfa_csrf=([^;]+)/)[1]"))


def _post(s: Session, path: str, data: Any = None) -> Any:
    reply = s.page.request.post(s.server.url + path, data=data, headers={"X-CSRF-Token": _csrf(s)})
    assert reply.ok, reply.text()
    return reply.json()


# Where each line's text starts and ends on screen: the rectangles of its first and last
# characters (a Range over the text node), and of the first character of each row it wraps to.
GEOMETRY = """(long) => {
  const pre = document.getElementById("cv-program");
  const span = [...pre.children].find((s) => s.textContent.includes(long));
  const text = span.firstChild;
  const at = (i, node = text) => {
    const r = document.createRange();
    r.setStart(node, i);
    r.setEnd(node, i + 1);
    return r.getBoundingClientRect();
  };
  const start = text.data.indexOf(long);
  const end = start + long.length - 1;
  const whole = document.createRange();
  whole.selectNodeContents(span);
  const rows = new Map(); // each row on screen (its top) -> where its first character is
  for (const r of whole.getClientRects()) {
    const top = Math.round(r.top);
    rows.set(top, Math.min(r.left, rows.get(top) ?? Infinity));
  }
  const other = [...pre.children].find((s) => s !== span && s.textContent.trim());
  return {
    panel: document.getElementById("cv-student").getBoundingClientRect().right,
    box: pre.getBoundingClientRect().right,
    lastRight: at(end).right,
    textLeft: at(start).left,
    rowLefts: [...rows.keys()].sort((a, b) => a - b).map((top) => rows.get(top)),
    numberLeft: at(0).left,
    otherNumberLeft: at(0, other.firstChild).left,
    scrollWidth: pre.scrollWidth,
    clientWidth: pre.clientWidth,
  };
}"""


def test_a_long_line_of_a_student_s_program_is_read_whole(
    open_session: Any, server: Server
) -> None:
    server.add_user("lina", role="instructor")
    server.add_user("dmitri", group="L2")  # handed to his group only: other tests' students
    # do not see this assignment
    teacher: Session = open_session("lina")
    files = {f.name: f.read_text(encoding="utf-8") for f in sorted(FOLDER.iterdir())}
    made = _post(teacher, "/api/assignments", {"files": files, "variants": False, "group": "L2"})

    student: Session = open_session("dmitri")
    opened = _post(student, f"/api/assignments/{made['id']}/open")
    ws = opened["mine"]["workspace_id"]
    state = student.page.request.get(f"{server.url}/api/workspaces/{ws}").json()
    program = f"{LONG}\n{state['program']}"
    saved = student.page.request.put(
        f"{server.url}/api/workspaces/{ws}",
        data={"base": state["revision"], "program": program, "points": state["points"]},
        headers={"X-CSRF-Token": _csrf(student)},
    )
    assert saved.ok, saved.text()

    page = teacher.open_page("/classroom")
    page.click(f'#cv-list button[data-id="{made["id"]}"]')
    page.locator("#cv-rows tr[data-student=dmitri]").get_by_role("button").click()
    expect(page.locator("#cv-student")).to_be_visible()
    expect(page.locator("#cv-program")).to_contain_text(LONG)
    g = page.evaluate(GEOMETRY, LONG)
    # The line's right end is inside the panel and its box: nothing to scroll sideways.
    assert g["lastRight"] <= g["box"] <= g["panel"], g
    assert g["scrollWidth"] <= g["clientWidth"], g
    # It wrapped, each row after the first starting under its text, right of the numbers.
    assert len(g["rowLefts"]) >= 2, g
    assert all(abs(left - g["textLeft"]) < 1 for left in g["rowLefts"][1:]), g
    assert abs(g["numberLeft"] - g["otherNumberLeft"]) < 1, g  # numbers in one column
    teacher.screenshot("classroom-long-line", toasts=False)

    # Opened read-only in the editor (the panel's link, the desk's Open work): wrapped too.
    teacher.page.goto(f"{server.url}/?workspace={ws}")
    teacher.wait_ready()
    expect(page.locator("#visit-banner")).to_be_visible()
    page.wait_for_function("() => window.melfa.editor.session.getUseWrapMode()")
    rows = teacher.eval(
        "() => { const s = window.melfa.editor.session;"
        " return [s.getScreenLength(), s.getLength()]; }"
    )
    assert rows[0] > rows[1], rows  # the long line takes more than one row on screen
    assert teacher.eval("() => window.melfa.editor.editor.renderer.scrollBarH.isVisible") is False
    teacher.screenshot("staff-reading-long-line", toasts=False)

    # The student's own editor does not wrap: their lines stay one row each as they type.
    student.open()
    assert student.eval("() => window.melfa.editor.session.getUseWrapMode()") is False


# From P2 to P1 at 10 %: the long line always moves the arm, wherever an earlier test left
# it, for long enough that the recorder samples it under any load (a move of a few tenths of
# a second fell between two samples in a loaded clean clone).
RUN_PROGRAM = f"SERVO ON\nMVS P2\nOVRD 10\nMOV P1 {COMMENT}\nEND\n"
RUN_POINTS = (
    "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,150.00,300.00,180.00,0.00,180.00)(7,0)\n"
)


def test_a_recorded_run_names_its_long_running_line_whole(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    """The replay's running line (a recorded run on the lab robot) is the whole step,
    wrapped in its box, not cut with an ellipsis."""
    server.add_user("zoe")
    s: Session = open_session("zoe")
    page = s.page
    free_the_robot(page, server)
    run = recorded_run(s, RUN_POINTS, RUN_PROGRAM)
    page.click("#runs-button")
    page.locator(f"#runs-list li[data-run='{run['id']}']").get_by_role(
        "button", name="Replay"
    ).click()
    expect(page.locator("#replay")).to_be_visible()
    frames = s.eval("() => window.melfa.runs.run.frames")
    index = frames["line"].index(4)  # a frame while MOV P1 ran
    s.eval(
        "(i) => { const r = document.getElementById('replay-slider'); r.value = String(i);"
        " r.dispatchEvent(new Event('input')); }",
        index,
    )
    shown = page.locator("#replay-line")
    expect(shown).to_have_text(f"line 4: MOV P1 {COMMENT}")
    box = shown.evaluate("(n) => [n.scrollWidth, n.clientWidth, n.getClientRects().length]")
    assert box[0] <= box[1], box  # nothing cut at its right edge
    s.screenshot("replay-long-line", toasts=False)
