"""The IDE's first page load and a reload: bytes on the wire and time, against the same
files sent uncompressed and uncached (the IDE before issue 16 sent 2.9 MB on every load).

Starts `melfa serve` (virtual robot, a temporary data folder) on a free loopback port,
signs in with Debian's Chromium (Playwright), opens the IDE, then reloads it. From the
browser's own Resource Timing entries, measured in one run:

1. first load: bytes transferred (``transferSize``: compressed bodies and headers) against
   the decoded size of the same files (what went on the wire with no compression);
2. reload: bytes transferred (cached vendor files cost 0, revalidated ones a bodiless 304)
   against the decoded size again (what an uncached reload sent);
3. time from navigation to the IDE ready (workspace open, first robot state), both loads.

Run: ``.venv/bin/python bench/bench_firstload.py``.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

from playwright.sync_api import Page, sync_playwright

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run"]
PASSWORD = "bench-firstload-admin-pw"
MEASURE = """() => {
  const entries = [...performance.getEntriesByType('navigation'),
                   ...performance.getEntriesByType('resource')];
  return {
    transferred: entries.reduce((s, e) => s + (e.transferSize || 0), 0),
    decoded: entries.reduce((s, e) => s + (e.decodedBodySize || 0), 0),
    files: entries.length,
  };
}"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def ready(page: Page) -> float:
    """Seconds from navigation start until the IDE is usable."""
    page.wait_for_function("() => window.melfa && window.melfa.workspace?.id && window.melfa.state")
    return float(page.evaluate("() => performance.now()")) / 1000


def main() -> None:
    data = Path(tempfile.mkdtemp(prefix="melfa-bench-"))
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    env = {**os.environ, "MELFA_ADMIN_PASSWORD": PASSWORD}
    env.pop("MELFA_ROBOT", None)
    server = subprocess.Popen(
        [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        env=env,
    )
    try:
        for _ in range(300):
            try:
                with urllib.request.urlopen(url + "/api/health", timeout=2) as reply:
                    if json.loads(reply.read())["robot"]["link"] == "connected":
                        break
            except OSError:
                time.sleep(0.1)
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            context = browser.new_context()
            context.request.post(
                url + "/api/session", data={"username": "admin", "password": PASSWORD}
            )
            page = context.new_page()
            page.goto(url + "/")
            first_s = ready(page)
            first = page.evaluate(MEASURE)
            page.reload()
            again_s = ready(page)
            again = page.evaluate(MEASURE)
            browser.close()
    finally:
        server.send_signal(signal.SIGINT)
        server.wait(timeout=15)
    for name, got, seconds in (("first load", first, first_s), ("reload", again, again_s)):
        wire, files = got["transferred"] / 1e6, got["decoded"] / 1e6
        print(
            f"{name}: {wire:.3f} MB on the wire of {files:.3f} MB of files "
            f"({wire / files:.3f}), {got['files']} files, ready in {seconds:.2f} s"
        )


if __name__ == "__main__":
    main()
