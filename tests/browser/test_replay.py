"""A run on the virtual lab robot is recorded and replays in the 3D view: the arm where it
was, the running line marked in the editor, the simulated path as a ghost beside the real
one and the largest deviation from it in the report; the live robot leaves the replay
alone until *Back to live*."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session, free_the_robot
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(180)

PROGRAM = "' a corner and back\nSERVO ON\nMOV P1\nMVS P2\nDLY 0.3\nMOV P1\nEND\n"
POINTS = (
    "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,150.00,300.00,180.00,0.00,180.00)(7,0)\n"
)


def _runs(s: Session) -> list[dict[str, Any]]:
    reply = s.context.request.get(s.server.url + "/api/runs")
    assert reply.ok, reply.text()
    return list(reply.json())


def recorded_run(s: Session, points: str, program: str) -> dict[str, Any]:
    """``program`` passed pre-flight, loaded and run on the lab robot by the page's student
    (the servo turned on by the run refusal's own fix), as recorded: the newest run."""
    page = s.page
    s.set_points(points)
    s.set_program(program)
    page.click("#act-preflight")
    expect(page.locator("#preflight")).to_have_attribute("data-passed", "true")
    page.click("#act-load")
    s.saw_toast("Project loaded")  # the page's first load: its toast lasts 4 s
    before = len(_runs(s))
    page.click("#act-run")
    page.locator(".toast.error").get_by_role("button", name="Turn on and retry").click()
    wait_until(lambda: len(_runs(s)) > before, what="the run to be recorded")
    return _runs(s)[0]


def test_a_recorded_run_replays_with_its_line_and_deviation(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s: Session = open_session("carol")
    page = s.page
    free_the_robot(page, server)
    run = recorded_run(s, POINTS, PROGRAM)
    assert run["user"] == "carol" and run["outcome"] == "finished"

    page.click("#runs-button")
    item = page.locator(f"#runs-list li[data-run='{run['id']}']")
    expect(item).to_contain_text("finished")
    s.screenshot("runs-list", toasts=False)
    item.get_by_role("button", name="Replay").click()
    replay = page.locator("#replay")
    expect(replay).to_be_visible()
    view = page.locator("#view3d")
    expect(view).to_have_attribute("data-replay-run", str(run["id"]))
    assert int(view.get_attribute("data-replay-ghost-points") or 0) > 2  # the pre-flight path
    assert int(view.get_attribute("data-replay-real-points") or 0) > 2  # the recorded one
    deviation = page.locator("#replay-deviation")
    expect(deviation).to_contain_text("Largest deviation")
    mm = float(deviation.get_attribute("data-mm") or "nan")
    # The figure shown is the report's. Its size is not bounded here: the lab robot of the
    # browser tests' shared server starts where earlier modules left it, pre-flight where
    # the student's simulator stands, so the first move can truly differ by many mm (the
    # alignment is tested in tests/service/test_recording_pure.py and bench_runs.py).
    assert mm == pytest.approx(run["report"]["deviation"]["mm"], abs=0.01)
    expect(page.locator("#replay-cycle")).to_contain_text("simulated")

    # The sample where the arm is furthest along +Y (on its way to P2): its line is marked.
    frames = s.eval("() => window.melfa.runs.run.frames")
    index = max(
        (i for i, line in enumerate(frames["line"]) if line and frames["pose"][i]),
        key=lambda i: frames["pose"][i][1],
    )
    line = frames["line"][index]
    s.eval(
        "(i) => { const r = document.getElementById('replay-slider'); r.value = String(i);"
        " r.dispatchEvent(new Event('input')); }",
        index,
    )
    expect(replay).to_have_attribute("data-line", str(line))
    expect(page.locator("#editor")).to_have_attribute("data-run-line", str(line))
    expect(page.locator("#replay-line")).to_contain_text(f"line {line}")
    shown = [round(v, 2) for v in frames["joints"][index]]
    assert s.joints() == shown
    # The live robot keeps streaming, and leaves the replayed arm where it is.
    seq = s.eval("() => window.melfa.state.seq")
    wait_until(lambda: s.eval("() => window.melfa.state.seq") > seq + 3, what="live states")
    assert s.joints() == shown
    assert page.get_attribute("#editor", "data-run-line") == str(line)
    s.screenshot("replay", toasts=False)

    page.click("#replay-close")
    expect(replay).to_be_hidden()
    live = [round(v, 2) for v in s.eval("() => window.melfa.state.joints")]
    wait_until(lambda: s.joints() == live or s.joints() != shown, what="the live arm back")


def test_a_student_sees_only_their_own_runs(open_session: Any, server: Server) -> None:
    """The list comes from the server's one rule: alice (no runs of her own here) sees none
    of carol's."""
    s: Session = open_session("alice")
    page = s.page
    page.click("#runs-button")
    expect(page.locator("#runs")).to_be_visible()
    expect(page.locator("#runs .runs-note")).to_contain_text(
        "No runs yet" if not _runs(s) else "Your runs"
    )
    assert all(r["user"] == "alice" for r in _runs(s))
