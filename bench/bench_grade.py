"""Grading speed: a class's pyramid submissions graded on this machine, and one check.

1. 40 pyramid-sized submissions (the thesis's exercise, examples/assignments/pyramid: the
   reference solution and its five typical wrong ones, in turn (7 references), each student
   with their own variant seed) graded as `melfa grade` grades them, in one process and in
   worker processes (one per core), against the issue's goal of 10 s;
2. one check of one submission (what *Check my solution* asks of the engine): the median
   wall and CPU time of `grade()` on the reference solution, over several runs;
3. *Check my solution* through a real `melfa serve`: an instructor publishes the pyramid
   with variants, a student opens it, saves the reference solution in their workspace (with
   their variant's points) and presses the button: the time from the request to the graded
   report (``POST /api/assignments/{id}/check``), over several presses; then the same
   student in the IDE in Debian's Chromium: from the click on *Check my solution* to the
   result shown beside the editor.

    .venv/bin/python bench/bench_grade.py
"""

from __future__ import annotations

import os
import statistics
import time
from pathlib import Path

import httpx

from melfa.cli.grade_commands import grade_all
from melfa.grade import (
    Assignment,
    Submission,
    grade,
    load_assignment,
    read_folder,
    variant_points,
)
from serving import STUDENT_PASSWORD, load, ms, serve, sign_in

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "assignments"
SOLUTIONS = EXAMPLE / "pyramid-solutions"
PROGRAMS = [
    "reference.MB4",
    *(f"wrong/{n}.MB4" for n in ("order", "high", "table", "no-hopen", "goto")),
]
CLASS = 40
GOAL_S = 10.0


def submissions(assignment: Assignment) -> list[tuple[Submission, str]]:
    """Student i: seed str(i), their variant's points, one of the six programs in turn."""
    texts = [(SOLUTIONS / p).read_text(encoding="utf-8") for p in PROGRAMS]
    out = []
    for i in range(CLASS):
        seed = str(i)
        points = variant_points(assignment, assignment.variant(seed))
        out.append((Submission(texts[i % len(texts)], points), seed))
    return out


def _cpu() -> float:
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def main() -> None:
    assignment = load_assignment(read_folder(EXAMPLE / "pyramid"))
    items = submissions(assignment)
    cores = os.cpu_count() or 1
    print(f"{CLASS} pyramid submissions, {len(assignment.spec.checks)} checks each, {cores} cores")
    for jobs in (1, cores):
        # every student has their own variant: the seed is the student's number here
        t0, c0 = time.perf_counter(), _cpu()
        load = os.getloadavg()[0]
        reports = grade_all(assignment, items, jobs)
        wall = time.perf_counter() - t0
        cpu = _cpu() - c0  # this process and its finished worker processes
        passed = sum(r.passed for r in reports)
        print(
            f"  {jobs} process{'es' if jobs > 1 else ''}: {wall:.2f} s wall "
            f"({wall / GOAL_S:.2f} × the {GOAL_S:g} s goal), CPU {cpu:.2f} s "
            f"({cpu / CLASS * 1000:.0f} ms per submission; {cpu / jobs / GOAL_S:.2f} × the goal "
            f"on {jobs} idle core{'s' if jobs > 1 else ''}); {passed} passed; load {load:.1f}"
        )
    walls, cpus = [], []
    reference, seed = items[0]
    for _ in range(9):
        t0, c0 = time.perf_counter(), time.process_time()
        grade(assignment, reference, seed)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    print(
        f"one check of the reference solution: median {statistics.median(walls) * 1000:.0f} ms "
        f"wall, {statistics.median(cpus) * 1000:.0f} ms CPU (min {min(walls) * 1000:.0f}, "
        f"max {max(walls) * 1000:.0f} ms wall; load average {os.getloadavg()[0]:.1f})"
    )

    button()


def _client(url: str, headers: dict[str, str]) -> httpx.Client:
    kept = {k: v for k, v in headers.items() if k != "token"}
    return httpx.Client(base_url=url, headers=kept, timeout=120)


def button(presses: int = 9) -> None:
    """*Check my solution* on a real server: request to graded report."""
    folder = EXAMPLE / "pyramid"
    files = {p.name: p.read_text(encoding="utf-8") for p in folder.iterdir() if p.is_file()}
    reference = (SOLUTIONS / "reference.MB4").read_text(encoding="utf-8")
    with serve(students=1, instructors=1) as (url, _pid):
        with _client(url, sign_in(url, "teach")) as teacher:
            made = teacher.post("/api/assignments", json={"files": files, "variants": True})
            if made.status_code == 404:
                print("check my solution: not measured (this server has no assignments yet)")
                return
            made.raise_for_status()
            assignment = made.json()["id"]
        with _client(url, sign_in(url, "s00")) as student:
            opened = student.post(f"/api/assignments/{assignment}/open")
            opened.raise_for_status()
            workspace = opened.json()["mine"]["workspace_id"]
            state = student.get(f"/api/workspaces/{workspace}").json()
            saved = student.put(
                f"/api/workspaces/{workspace}",
                json={"base": state["revision"], "program": reference, "points": state["points"]},
            )
            saved.raise_for_status()
            times = []
            passed = []
            for _ in range(presses):
                t0 = time.perf_counter()
                reply = student.post(f"/api/assignments/{assignment}/check")
                times.append(time.perf_counter() - t0)
                reply.raise_for_status()
                passed.append(reply.json()["report"]["passed"])
        print(
            f"check my solution through melfa serve, {presses} presses: {ms(times)} "
            f"(the issue's budget 2 s); passed {sum(passed)} of {presses}; load {load()}"
        )
        in_browser(url, presses)


CHROMIUM = Path("/usr/bin/chromium")


def in_browser(url: str, presses: int) -> None:
    """The student's click on *Check my solution* in the IDE to the result on the page."""
    if not CHROMIUM.exists():
        print("in the IDE: not measured (no /usr/bin/chromium)")
        return
    from playwright.sync_api import sync_playwright

    times = []
    with sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=str(CHROMIUM), args=["--headless", "--no-sandbox", "--disable-gpu"]
        )
        context = browser.new_context(viewport={"width": 1366, "height": 768})
        context.add_init_script("localStorage.setItem('melfa.guide.s00', 'done')")
        context.set_default_timeout(120_000)
        login = {"username": "s00", "password": STUDENT_PASSWORD}
        assert context.request.post(url + "/api/session", data=login).ok
        page = context.new_page()
        page.goto(url + "/")
        page.wait_for_function("() => window.melfa && window.melfa.workspace?.id")
        page.click("#assign-open")
        page.locator("#assign-dialog .assign-row").first.get_by_role("button").click()
        page.wait_for_selector("#assign-check:visible")
        for _ in range(presses):
            page.evaluate(
                "() => { const s = document.getElementById('assign-summary');"
                " delete s.dataset.passed; s.textContent = ''; }"
            )
            t0 = time.perf_counter()
            page.click("#assign-check")
            page.wait_for_selector(
                "#assign-summary[data-passed=true], #assign-summary[data-passed=false]"
            )
            times.append(time.perf_counter() - t0)
        shown = page.get_attribute("#assign-summary", "data-passed")
        browser.close()
    print(
        f"in the IDE (Chromium), click to result, {presses} presses: {ms(times)}; "
        f"last result passed={shown}; load {load()}"
    )


if __name__ == "__main__":
    main()
