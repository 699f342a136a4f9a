"""`/api/assignments` on the real app and a real SQLite file, graded by the real engine on
the simulated RV-6S: an instructor reads and publishes a folder with variants; students
open it (a workspace with their own variant's starter), check, fail on the right line, fix,
pass and submit within the attempts; the class view, its filters and CSV; the folder
exported as imported; and who may see what."""

from __future__ import annotations

import csv
import io
import zipfile
from datetime import UTC, datetime, timedelta
from pathlib import Path

from melfa.lang.plan import plan_upload
from melfa.store import ClassRow, Enrolment, GradeKind, SubmissionSummary
from melfa.store.runs import NewRun
from melfa.vocab.classroom import COLUMN_WORDS, ClassColumn, ClassFilter
from melfa.web import classroom
from tests.web.conftest import Browser, Web, assert_error

FOLDER = Path(__file__).parent / "assignments" / "place-block"
FILES = {p.name: p.read_text(encoding="utf-8") for p in FOLDER.iterdir()}
FIX = "MVS P1, 50\nEND"


def _publish(web: Web, **extra: object) -> dict[str, object]:
    made = web.ivy.post("/api/assignments", json={"files": FILES, "variants": True, **extra})
    assert made.status_code == 201, made.text
    return dict(made.json())


def _open(who: Browser, assignment_id: object) -> dict[str, object]:
    opened = who.post(f"/api/assignments/{assignment_id}/open")
    assert opened.status_code == 200, opened.text
    return dict(opened.json())


def _save(who: Browser, workspace_id: int, program: str) -> None:
    state = who.get(f"/api/workspaces/{workspace_id}").json()
    saved = who.put(
        f"/api/workspaces/{workspace_id}",
        json={"base": state["revision"], "program": program, "points": state["points"]},
    )
    assert saved.status_code == 200, saved.text


def test_folder_is_read_before_publishing_and_problems_say_where(web: Web) -> None:
    read = web.ivy.post("/api/assignments/folder", json={"files": FILES}).json()
    assert (read["title"], read["problems"], read["attempts"]) == ("Reach the block", [], 3)
    assert [c["kind"] for c in read["checks"]] == ["final-pose", "no-collision", "avoids"]
    assert read["variants"] == ["pick"]
    assert "<strong>50 mm below</strong>" in read["statement_html"]

    broken = dict(FILES, **{"assignment.toml": FILES["assignment.toml"] + "\n[[checks]]\n"})
    problems = web.ivy.post("/api/assignments/folder", json={"files": broken}).json()
    assert problems["title"] is None and problems["problems"]
    assert problems["problems"][0]["file"] == "assignment.toml"
    refused = web.ivy.post("/api/assignments", json={"files": broken})
    body = assert_error(refused, 422, "invalid-assignment")
    assert body["detail"]["problems"] and "assignment.toml" in body["message"]
    assert web.ivy.get("/api/assignments").json()["assignments"] == []  # nothing stored


def test_students_check_fail_on_the_line_fix_pass_and_submit(web: Web) -> None:
    made = _publish(web)
    assert (made["attempts"], made["variants"]) == (3, True)  # from the assignment.toml
    ann = _open(web.ann, made["id"])
    cat = _open(web.cat, made["id"])
    assert ann["mine"]["seed"] != cat["mine"]["seed"]
    ann_ws, cat_ws = ann["mine"]["workspace_id"], cat["mine"]["workspace_id"]
    ann_points = web.ann.get(f"/api/workspaces/{ann_ws}").json()["points"]
    cat_points = web.cat.get(f"/api/workspaces/{cat_ws}").json()["points"]
    assert ann_points != cat_points  # two students, two places for P1
    assert ann["mine"]["variant"] and ann["cell"] is not None
    assert _open(web.ann, made["id"])["mine"]["workspace_id"] == ann_ws  # made once

    failed = web.ann.post(f"/api/assignments/{made['id']}/check").json()
    assert failed["report"]["passed"] is False
    pose = failed["report"]["checks"][0]
    assert (pose["kind"], pose["passed"], pose["line"]) == ("final-pose", False, 3)
    assert failed["grading"]["kind"] == "check" and failed["attempts_left"] == 3

    program = web.ann.get(f"/api/workspaces/{ann_ws}").json()["program"]
    _save(web.ann, ann_ws, program.replace("END", FIX))
    passed = web.ann.post(f"/api/assignments/{made['id']}/check").json()
    assert passed["report"]["passed"] and passed["grading"]["preflight"] is True
    submitted = web.ann.post(f"/api/assignments/{made['id']}/submit").json()
    assert submitted["grading"]["kind"] == "submit" and submitted["report"]["passed"]
    assert submitted["grading"]["revision"] == passed["grading"]["revision"] == 2
    assert submitted["attempts_left"] == 2

    # cat's text passes only with her own P1: ann's fixed program on cat's points is hers
    _save(web.cat, cat_ws, program.replace("END", FIX))
    assert web.cat.post(f"/api/assignments/{made['id']}/check").json()["report"]["passed"]

    mine = web.ann.get("/api/assignments").json()["assignments"][0]["mine"]
    assert mine["best"]["passed"] and mine["latest"]["kind"] == "submit"
    history = web.ann.get(f"/api/assignments/{made['id']}/history").json()["gradings"]
    assert [g["kind"] for g in history] == ["submit", "check", "check"]


def test_attempts_run_out(web: Web) -> None:
    made = _publish(web, attempts=1)
    _open(web.ann, made["id"])
    assert web.ann.post(f"/api/assignments/{made['id']}/submit").status_code == 200
    closed = web.ann.post(f"/api/assignments/{made['id']}/submit")
    assert "every attempt is used" in assert_error(closed, 422, "submissions-closed")["message"]
    assert web.ann.post(f"/api/assignments/{made['id']}/check").status_code == 200


def test_class_view_filters_and_csv(web: Web) -> None:
    made = _publish(web)
    ann = _open(web.ann, made["id"])
    ws = ann["mine"]["workspace_id"]
    web.ann.post(f"/api/assignments/{made['id']}/check")
    _save(web.ann, ws, web.ann.get(f"/api/workspaces/{ws}").json()["program"].replace("END", FIX))
    web.ann.post(f"/api/assignments/{made['id']}/submit")

    # A run on the lab robot of the text she submitted (recorded by the service), and one
    # of another text: only the first counts.
    state = web.ann.get(f"/api/workspaces/{ws}").json()
    for program, at in ((state["program"], 1), ("MOV P1\nEND\n", 2)):
        web.store.runs.save(
            NewRun("lab", "ann", datetime.now(UTC) + timedelta(seconds=at), 5.0, "finished",
                   plan_upload(program, state["points"]).fingerprint, "ann", program, 0, b"")
        )  # fmt: skip

    view = web.ivy.get(f"/api/assignments/{made['id']}/class").json()
    rows = {r["student"]: r for r in view["rows"]}
    assert (rows["ann"]["ran_on_arm"], rows["bob"]["ran_on_arm"]) == (1, 0)
    assert sorted(rows) == ["ann", "bob", "cat"]
    a = rows["ann"]
    assert (a["checks"], a["submissions"], a["attempts_left"]) == (1, 1, 2)
    assert a["best"]["passed"] and a["latest"]["preflight"] and a["last_saved"]
    assert rows["bob"]["opened"] is None and rows["bob"]["latest"] is None
    passed = web.ivy.get(f"/api/assignments/{made['id']}/class?filter=passed").json()
    assert [r["student"] for r in passed["rows"]] == ["ann"]
    unopened = web.ivy.get(f"/api/assignments/{made['id']}/class?filter=not-opened").json()
    assert [r["student"] for r in unopened["rows"]] == ["bob", "cat"]

    reply = web.ivy.get(f"/api/assignments/{made['id']}/class.csv")
    assert reply.headers["content-type"].startswith("text/csv")
    assert "Reach-the-block-class.csv" in reply.headers["content-disposition"]
    table = list(csv.reader(io.StringIO(reply.text)))
    assert table[0] == [COLUMN_WORDS[c] for c in ClassColumn]
    by_name = {r[0]: dict(zip(table[0], r, strict=True)) for r in table[1:]}
    assert by_name["ann"]["Best submission"] == "every check passed"
    assert by_name["ann"]["Pre-flight"] == "passed"
    assert by_name["bob"]["Latest check"] == "not opened"
    assert (by_name["ann"]["Ran on the arm"], by_name["bob"]["Ran on the arm"]) == ("1", "0")

    zipped = web.ivy.get(f"/api/assignments/{made['id']}/export")
    with zipfile.ZipFile(io.BytesIO(zipped.content)) as z:
        again = {n.split("/", 1)[1]: z.read(n).decode() for n in z.namelist()}
    assert again == FILES
    form = {"file": ("block.zip", zipped.content, "application/zip")}
    assert web.ivy.post("/api/assignments/folder.zip", files=form).json()["files"] == FILES


def test_student_and_instructor_read_one_summary_of_a_grading(web: Web) -> None:
    """Checks passed of checks, and the points when the checks have weights: the same
    words in the student's reply, their history, the class view and its CSV (the class
    view once said "failed · 2 of 4" where the student read "2 of 3 checks passed")."""
    toml = FILES["assignment.toml"].replace("tolerance_mm = 1\n", "tolerance_mm = 1\nweight = 2\n")
    made = web.ivy.post(
        "/api/assignments", json={"files": dict(FILES, **{"assignment.toml": toml})}
    )
    assert made.status_code == 201, made.text
    aid = made.json()["id"]
    _open(web.ann, aid)
    checked = web.ann.post(f"/api/assignments/{aid}/check").json()["grading"]
    words = "2 of 3 checks passed, 2 of 4 points"
    assert (checked["checks_passed"], checked["checks"], checked["summary"]) == (2, 3, words)
    history = web.ann.get(f"/api/assignments/{aid}/history").json()["gradings"]
    assert history[0]["summary"] == words
    rows = {r["student"]: r for r in web.ivy.get(f"/api/assignments/{aid}/class").json()["rows"]}
    assert rows["ann"]["latest"]["summary"] == words
    table = list(csv.reader(io.StringIO(web.ivy.get(f"/api/assignments/{aid}/class.csv").text)))
    by_name = {r[0]: dict(zip(table[0], r, strict=True)) for r in table[1:]}
    assert by_name["ann"]["Latest check"] == words


def test_who_may_see_what(web: Web) -> None:
    for_g2 = _publish(web, group="G2")
    assert web.ann.get("/api/assignments").json()["assignments"] == []  # ann is in G1
    assert_error(web.ann.post(f"/api/assignments/{for_g2['id']}/open"), 403, "forbidden")
    assert_error(web.cat.get(f"/api/assignments/{for_g2['id']}/class"), 403, "forbidden")
    assert_error(web.cat.post("/api/assignments", json={"files": FILES}), 403, "forbidden")
    assert_error(web.cat.get(f"/api/assignments/{for_g2['id']}/export"), 403, "forbidden")
    assert_error(web.cat.post(f"/api/assignments/{for_g2['id']}/check"), 409, "not-opened")
    _open(web.cat, for_g2["id"])
    graded = web.cat.post(f"/api/assignments/{for_g2['id']}/check").json()["grading"]
    report = web.ivy.get(f"/api/assignments/{for_g2['id']}/gradings/{graded['id']}")
    assert report.json()["student"] == "cat"
    everyone = _publish(web)
    _open(web.ann, everyone["id"])
    assert_error(
        web.ann.get(f"/api/assignments/{everyone['id']}/history?student=cat"), 403, "forbidden"
    )
    assert web.ivy.get("/api/assignments/groups").json()["groups"] == ["G1", "G2"]
    assert_error(web.ann.get("/api/assignments/99"), 404, "not-found")


def test_the_class_view_page_is_for_staff(web: Web) -> None:
    """``/classroom``: sign in first (and come back), a student is told it is not theirs."""
    anonymous = web.client.get("/classroom", follow_redirects=False)
    assert anonymous.status_code == 303
    assert anonymous.headers["location"] == "/login?next=/classroom"
    refused = web.ann.get("/classroom")
    assert refused.status_code == 403 and "Only instructors and admins" in refused.text
    page = web.ivy.get("/classroom")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert "class view" in page.text


def _row(opened_min_ago: float | None, passed: bool | None) -> ClassRow:
    now = datetime(2026, 1, 1, 12, tzinfo=UTC)
    copy = None
    if opened_min_ago is not None:
        copy = Enrolment(1, 1, "ann", 1, 1, now - timedelta(minutes=opened_min_ago))
    best = None
    if passed is not None:
        best = SubmissionSummary(1, GradeKind.SUBMIT, 1, now, passed, 1.0, True)
    return ClassRow(
        "ann", "", None, copy, best, best, 0, 0 if best is None else 1, None, None,
        now if passed else None,
    )  # fmt: skip


def test_filters() -> None:
    now = datetime(2026, 1, 1, 12, tzinfo=UTC)
    stuck = _row(31, False)
    fresh = _row(5, None)
    done = _row(45, True)
    unopened = _row(None, None)
    rows = [stuck, fresh, done, unopened]

    def which(f: ClassFilter) -> list[ClassRow]:
        return [r for r in rows if classroom.matches(r, f, now)]

    assert which(ClassFilter.STUCK) == [stuck]
    assert which(ClassFilter.PASSED) == [done]
    assert which(ClassFilter.NOT_OPENED) == [unopened]
    assert which(ClassFilter.NOT_SUBMITTED) == [fresh]
    assert which(ClassFilter.ALL) == rows


EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "assignments"


def test_the_pyramid_example_through_the_server(web: Web) -> None:
    """The thesis's exercise as shipped: published with variants, the reference solution
    passes for two students with different positions; GOTO instead of GOSUB fails there."""
    files = {p.name: p.read_text(encoding="utf-8") for p in (EXAMPLES / "pyramid").iterdir()}
    made = web.ivy.post("/api/assignments", json={"files": files, "variants": True}).json()
    solutions = EXAMPLES / "pyramid-solutions"
    reference = (solutions / "reference.MB4").read_text(encoding="utf-8")
    points = set()
    for who in (web.ann, web.cat):
        ws = _open(who, made["id"])["mine"]["workspace_id"]
        points.add(who.get(f"/api/workspaces/{ws}").json()["points"])
        _save(who, ws, reference)
        report = who.post(f"/api/assignments/{made['id']}/check").json()["report"]
        assert report["passed"], [c for c in report["checks"] if not c["passed"]]
    assert len(points) == 2
    _save(web.ann, _open(web.ann, made["id"])["mine"]["workspace_id"],
          (solutions / "wrong" / "goto.MB4").read_text(encoding="utf-8"))  # fmt: skip
    report = web.ann.post(f"/api/assignments/{made['id']}/check").json()["report"]
    failed = {c["kind"] for c in report["checks"] if not c["passed"]}
    assert "avoids" in failed and "uses" in failed


def test_the_debugger_runs_an_assignment_in_its_cell(web: Web) -> None:
    """On their own simulator a student debugs an assignment's workspace in the
    assignment's cell (their variant's parts); any other text in the lab's cell."""
    files = {p.name: p.read_text(encoding="utf-8") for p in (EXAMPLES / "pyramid").iterdir()}
    made = web.ivy.post("/api/assignments", json={"files": files, "variants": True}).json()
    ws = _open(web.ann, made["id"])["mine"]["workspace_id"]
    state = web.ann.get(f"/api/workspaces/{ws}").json()
    body = {"program": state["program"], "points": state["points"], "check": False}
    assert web.ann.post("/api/debug", json=body).status_code == 200
    target = web.app.state.web.targets.private("ann")
    assert target.debug.cell is None  # the lab's cell has no parts
    started = web.ann.post("/api/debug", json={**body, "workspace_id": ws})
    assert started.status_code == 200, started.text
    names = {p.name for p in target.debug.cell.parts()}
    assert {f"block {n}" for n in range(1, 7)} <= names
