"""How long `melfa serve` takes to end after Ctrl-C, as a lab technician meets it.

Each round starts `melfa serve` on a fresh database as a terminal's foreground job (its own
process group, the check and load-plan worker processes in it), signs a student in, runs a
looping motion program on the student's private simulator ("My simulator") and opens the
IDE in a Chromium tab (its WebSocket and keep-alive connections stay open). Then SIGINT to
the whole group, as Ctrl-C on a terminal sends it, and measured: the time until the server
process has exited, and until every process of the group is gone; its exit status (130 is
the command line's Ctrl-C convention) and whether it said "melfa stopped" without a
traceback (or "Exception ignored", as Python's exit handler prints one).

Run: ``.venv/bin/python bench/bench_ctrl_c.py [--rounds 3] [--no-browser]``.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

from serving import STUDENT_PASSWORD, load, sign_in, wait_healthy

CHROMIUM = Path("/usr/bin/chromium")
PROGRAM = "SERVO ON\n*LOOP\nMOV P1\nMOV P2\nGOTO *LOOP\nEND\n"
POINTS = (
    "DEF POS P1=(350.00,-150.00,400.00,180.00,0.00,180.00)(7,0)\n"
    "DEF POS P2=(350.00,150.00,300.00,180.00,0.00,180.00)(7,0)\n"
)
MINE = {"target": "mine"}


def _start(data: Path) -> tuple[subprocess.Popen[str], str]:
    from argon2 import PasswordHasher

    from melfa.store import Store

    hasher = PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)
    with Store.open_dir(data, hasher=hasher) as store:
        store.accounts.ensure_admin("bench-lantern-9")
        store.accounts.create_user("s00", STUDENT_PASSWORD)
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT",)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "melfa", "serve", "--port", "0", "--data", str(data)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        env=env,
        start_new_session=True,  # a terminal's foreground job: Ctrl-C reaches the group
    )
    assert proc.stdout is not None
    for line in proc.stdout:
        found = re.search(r"serving on (http://127\.0\.0\.1:\d+)/", line)
        if found:
            return proc, found.group(1)
    raise SystemExit(f"melfa serve did not start (status {proc.wait()})")


def _group_alive(pgid: int) -> bool:
    """Whether a process of the group still runs (a zombie does not: here it waits for the
    container's init to reap it, which a real init does at once)."""
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            return True
    return False


def _round(browser: object | None) -> tuple[float, float, int | None, str]:
    data = Path(tempfile.mkdtemp(prefix="melfa-bench-ctrl-c-"))
    proc, url = _start(data)
    page_context = None
    try:
        wait_healthy(url)
        headers = sign_in(url, "s00")
        token = headers.pop("token")
        with httpx.Client(base_url=url, headers=headers, timeout=30) as c:
            for path, body in (
                ("/api/robot/servo", {"on": True}),
                ("/api/robot/project", {"program": PROGRAM, "points": POINTS}),
                ("/api/robot/run", None),
            ):
                c.post(path, json=body, params=MINE).raise_for_status()
            for _ in range(100):
                if c.get("/api/robot/state", params=MINE).json().get("running"):
                    break
                time.sleep(0.1)
            else:
                raise SystemExit("the private simulator's program did not start")
        if browser is not None:
            page_context = browser.new_context()  # type: ignore[attr-defined]
            page_context.add_cookies([{"name": "melfa_session", "value": token, "url": url}])
            page = page_context.new_page()
            page.goto(url + "/")
            page.wait_for_selector("#web-status[data-state=up]", timeout=60_000)
            page.wait_for_timeout(1000)  # the tab settles: its socket streams state
        pgid = proc.pid
        began = time.perf_counter()
        os.killpg(pgid, signal.SIGINT)
        status = proc.wait(timeout=120)
        server_s = time.perf_counter() - began
        while _group_alive(pgid) and time.perf_counter() - began < 120:
            time.sleep(0.01)
        group_s = time.perf_counter() - began
        assert proc.stdout is not None
        said = proc.stdout.read()
        words = "melfa stopped" if "melfa stopped" in said else "no 'melfa stopped'"
        if "Traceback" in said:
            words += ", TRACEBACK"
        if "Exception ignored" in said:
            words += ", EXCEPTION IGNORED"
        return server_s, group_s, status, words
    finally:
        if page_context is not None:
            page_context.close()
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--no-browser", action="store_true", help="no Chromium tab open")
    args = parser.parse_args()
    print(f"load average before: {load()}")
    server: list[float] = []
    group: list[float] = []

    def rounds(browser: object | None) -> None:
        for n in range(args.rounds):
            server_s, group_s, status, words = _round(browser)
            server.append(server_s)
            group.append(group_s)
            print(
                f"round {n + 1}: server exited in {server_s:5.2f} s, every process of the "
                f"group in {group_s:5.2f} s; status {status}; {words}",
                flush=True,
            )

    if args.no_browser or not CHROMIUM.exists():
        rounds(None)
    else:
        from playwright.sync_api import sync_playwright

        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=str(CHROMIUM), args=["--no-sandbox"])
            rounds(browser)
            browser.close()
    print(
        f"Ctrl-C to exit, {args.rounds} rounds: server median {statistics.median(server):.2f} s "
        f"(max {max(server):.2f} s); whole group median {statistics.median(group):.2f} s "
        f"(max {max(group):.2f} s); load average after: {load()}"
    )


if __name__ == "__main__":
    main()
