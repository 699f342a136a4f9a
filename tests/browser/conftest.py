"""Browser tests: `melfa serve` for real (a subprocess on a free port, a temp data dir) and
Debian's Chromium driven by Playwright's sync API. Never a downloaded browser: Chromium is
launched by its path (scripts/test installs it with apt-get)."""

from __future__ import annotations

import contextlib
import json
import os
import re
import subprocess
import sys
import tempfile
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, BrowserContext, Locator, Page, expect, sync_playwright
from playwright.sync_api import TimeoutError as PlaywrightTimeoutError

from tests.serving import melfa_serve as serving_melfa

CHROMIUM = Path("/usr/bin/chromium")
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
ADMIN_PASSWORD = "browser-tests-admin-pw"
ROOT = Path(__file__).resolve().parents[2]
# The committed screenshots (docs/screenshots, linked from docs/ide.md) are refreshed with
# MELFA_UPDATE_SCREENSHOTS=1; ordinary runs write them to a temporary folder so a test run
# never dirties the working tree.
SCREENSHOTS = (
    ROOT / "docs" / "screenshots"
    if os.environ.get("MELFA_UPDATE_SCREENSHOTS")
    else Path(tempfile.gettempdir()) / "melfa-screenshots"
)
VIEWPORT = {"width": 1366, "height": 768}

HANG_GUARD_MS = 15_000
"""How long an `expect`, a `wait_for_*` or an action (a click waits for its target to be
visible, enabled and not covered) waits for what the page should come to: a guard against a
hang, not a measure (tests never time things). Playwright's 5 s (30 s for actions) was short
for a check answered by a worker process at niceness +10 on two cores busy with the suite."""
OPEN_GUARD_MS = 60_000
"""The guard for opening the IDE (sign-in, ~40 modules, three.js and Ace, the live socket,
the workspace's live document): the heaviest step of a test; CI under a second suite (load
12-14 on 2 cores) saw it take over 10 s."""
expect.set_options(timeout=HANG_GUARD_MS)


@dataclass(frozen=True)
class Server:
    url: str
    data: Path
    passwords: dict[str, str]

    def add_user(self, name: str, role: str = "student", group: str | None = None) -> str:
        """Create an account with the `melfa users add` CLI; returns its password. The
        server is the whole session's: each test file adds names of its own
        (`test_users_of_their_own`)."""
        command = [sys.executable, "-m", "melfa", "users", "add", name, "--role", role]
        if group is not None:
            command += ["--group", group]
        out = subprocess.run(
            [*command, "--generate", "--data", str(self.data)],
            capture_output=True,
            text=True,
            check=True,
            timeout=60,
        )
        password = out.stdout.strip().splitlines()[-1]
        self.passwords[name] = password
        return password


@contextlib.contextmanager
def melfa_serve(data: Path, *extra: str, timeout: float = 120.0) -> Iterator[str]:
    """`tests.serving.melfa_serve` with the browser tests' admin password."""
    with serving_melfa(data, *extra, admin_password=ADMIN_PASSWORD, timeout=timeout) as url:
        yield url


@contextlib.contextmanager
def serving(data: Path, *extra: str) -> Iterator[Server]:
    """`melfa_serve` with three students (alice, bob, carol)."""
    with melfa_serve(data, *extra) as url:
        server = Server(url, data, {"admin": ADMIN_PASSWORD})
        for name in ("alice", "bob", "carol"):
            server.add_user(name)
        yield server


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    with serving(tmp_path_factory.mktemp("melfa-data")) as running:
        yield running


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    """Chromium for one test module. Not for the session: Playwright's sync API keeps an
    asyncio loop running in the main thread until it stops, and every later test that
    calls asyncio.run() would fail."""
    if not CHROMIUM.exists():  # pragma: no cover - scripts/test installs it
        pytest.skip("Debian's chromium is not at /usr/bin/chromium (apt-get install chromium)")
    if not (ROOT / "src/melfa/web/static/vendor/.stamp").is_file():  # pragma: no cover
        pytest.skip("the IDE's vendored libraries are missing: run scripts/build-frontend")
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=ARGS)
        yield browser
        browser.close()


TOAST_LOG = """
window.__toasts = [];
new MutationObserver((changes) => {
  for (const change of changes)
    for (const node of change.addedNodes)
      if (node.nodeType === 1 && node.classList.contains("toast"))
        queueMicrotask(() => window.__toasts.push(node.innerText));
}).observe(document, { childList: true, subtree: true });
"""
"""Every toast a page showed, in order (a toast leaves after 4 s: a test on a loaded machine
may look only after that)."""


class Session:
    """One signed-in browser context with the IDE open."""

    def __init__(
        self, browser: Browser, server: Server, user: str, *, first_run: bool = False
    ) -> None:
        self.server = server
        self.user = user
        self.context: BrowserContext = browser.new_context(viewport=VIEWPORT)  # type: ignore[arg-type]
        if not first_run:  # the first-run guide was seen (test_guide.py wants it unseen)
            self.context.add_init_script(f"localStorage.setItem('melfa.guide.{user}', 'done')")
        self.context.add_init_script(TOAST_LOG)
        self.context.set_default_timeout(HANG_GUARD_MS)
        self.errors: list[str] = []
        self.page: Page = self.context.new_page()
        self.page.on("pageerror", lambda exc: self.errors.append(str(exc)))

    def login_api(self) -> None:
        """Sign in through the API (the login form has its own test)."""
        reply = self.context.request.post(
            self.server.url + "/api/session",
            data={"username": self.user, "password": self.server.passwords[self.user]},
        )
        assert reply.ok, reply.text()
        self.open()

    def open(self) -> None:
        self.page.goto(self.server.url + "/", timeout=OPEN_GUARD_MS)
        self.wait_ready()

    def wait_ready(self) -> None:
        page, guard = self.page, OPEN_GUARD_MS
        try:
            page.wait_for_selector("#web-status[data-state=up]", timeout=guard)
        except PlaywrightTimeoutError:  # say what the page showed instead
            shown = self.eval(
                "() => [document.getElementById('web-status')?.outerHTML, window.__toasts]"
            )
            raise AssertionError(f"the live socket not up in {guard} ms: {shown}") from None
        page.wait_for_function("() => window.melfa && window.melfa.workspace?.id", timeout=guard)
        # The live document is here (co-editing: the editor is read-only until it is).
        page.wait_for_function("() => window.melfa.workspace.live?.synced", timeout=guard)
        page.wait_for_function("() => window.melfa.state?.joints", timeout=guard)
        # main.js has finished: every panel is in place and an empty workspace has its
        # welcome project (it came mid-test, after a test had set its own points).
        page.wait_for_selector("body[data-ready=true]", state="attached", timeout=guard)

    def eval(self, script: str, arg: Any = None) -> Any:
        return self.page.evaluate(script, arg)

    def set_program(self, text: str) -> None:
        self.eval("(t) => window.melfa.editor.editor.setValue(t, 1)", text)

    def set_points(self, text: str) -> None:
        self.eval("(t) => window.melfa.workspace.update({points: t})", text)

    def checked_problem(self, points: str, program: str, says: str) -> Locator:
        """The problems list's row that says ``says`` after *Check* of ``program`` with
        ``points`` (as a student types them in, then presses the button)."""
        self.set_points(points)
        self.set_program(program)
        self.page.click("#act-check")
        return self.page.locator("#problem-list li", has_text=says)

    def saw_toast(self, pattern: str, timeout: float = 30_000) -> str:
        """The first toast since the page loaded whose text matches the regular expression
        ``pattern``, waiting up to ``timeout`` ms for it (gone again or not)."""
        try:
            found = self.page.wait_for_function(
                "(p) => window.__toasts.find((t) => new RegExp(p).test(t))",
                arg=pattern,
                timeout=timeout,
            )
        except PlaywrightTimeoutError:  # say what the page did show instead
            shown = self.eval("() => window.__toasts")
            raise AssertionError(f"no toast {pattern!r} in {timeout} ms; shown: {shown}") from None
        return str(found.json_value())

    def joints(self) -> list[float]:
        return json.loads(self.page.get_attribute("#view3d", "data-joints") or "[]")

    def pose(self) -> list[float]:
        return list(self.eval("() => window.melfa.state.pose"))

    def open_page(self, path: str) -> Page:
        """A page other than the IDE (``/desk``, ``/classroom``), once its script is ready."""
        self.page.goto(self.server.url + path)
        self.page.wait_for_selector("body[data-ready=true]")
        return self.page

    def screenshot(self, name: str, *, toasts: bool = True) -> None:
        """For the docs; ``toasts=False``: what the test is about, earlier steps' toasts put
        away."""
        if not toasts:
            self.eval("() => document.querySelectorAll('.toast').forEach((t) => t.remove())")
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        self.page.mouse.move(0, 0)
        self.page.screenshot(path=str(SCREENSHOTS / f"{name}.png"))

    def close(self) -> None:
        self.context.close()
        assert not self.errors, self.errors


def free_the_robot(page: Page, server: Server) -> None:
    """Stop, clear any alarm, switch the servo off and release control as admin: the test
    that calls it (and the next one) finds a free, idle robot as a student's first hour does."""
    admin = page.context.browser.new_context()  # type: ignore[union-attr]
    try:
        reply = admin.request.post(
            server.url + "/api/session",
            data={"username": "admin", "password": server.passwords["admin"]},
        )
        token = reply.json()["csrf_token"]
        headers = {"X-CSRF-Token": token}
        admin.request.post(server.url + "/api/robot/stop", headers=headers)
        admin.request.post(server.url + "/api/lease/takeover", headers=headers)
        admin.request.post(server.url + "/api/robot/reset-alarm", headers=headers)
        admin.request.post(server.url + "/api/robot/servo", data={"on": False}, headers=headers)
        admin.request.delete(server.url + "/api/lease", headers=headers)
    finally:
        admin.close()


@pytest.fixture
def open_session(browser: Browser, server: Server) -> Iterator[Any]:
    """Factory: `open_session("alice")` gives a signed-in IDE; all closed afterwards."""
    sessions: list[Session] = []

    def make(user: str, *, login: bool = True, first_run: bool = False) -> Session:
        session = Session(browser, server, user, first_run=first_run)
        sessions.append(session)
        if login:
            session.login_api()
        return session

    yield make
    for session in sessions:
        session.close()


SIGNED_OUT = re.compile(r"/login(\?next=[^&]*)?$")
"""The sign-in page after a sign-out: straight there, or through a request of the page that
the ended session answered 401 first (api.js then adds where the student was)."""


@pytest.fixture
def stop_robot(server: Server) -> Iterator[None]:
    """Leave the shared robot idle for the next test."""
    yield
    body = json.dumps({"username": "admin", "password": ADMIN_PASSWORD}).encode()
    request = urllib.request.Request(
        server.url + "/api/session", body, {"Content-Type": "application/json"}
    )
    with urllib.request.urlopen(request, timeout=30) as reply:
        token = json.loads(reply.read())["csrf_token"]
        cookies = "; ".join(c.split(";")[0] for c in reply.headers.get_all("Set-Cookie") or [])
    stop = urllib.request.Request(
        server.url + "/api/robot/stop",
        b"",
        {"X-CSRF-Token": token, "Cookie": cookies},
        method="POST",
    )
    urllib.request.urlopen(stop, timeout=30).close()


AXE = ROOT / "frontend" / "node_modules" / "axe-core" / "axe.min.js"


def axe_serious(page: Page) -> list[str]:
    """axe-core's serious and critical findings on the page as it is now, one line each.
    Injected through DevTools, not a <script>: the IDE's Content-Security-Policy forbids
    inline scripts. Skips the test when axe-core is not installed."""
    if not AXE.is_file():  # pragma: no cover - scripts/setup installs it
        pytest.skip("axe-core is not installed: run scripts/build-frontend")
    page.evaluate(AXE.read_text(encoding="utf-8") + "\n;0")
    return [
        f"{v['id']} ({v['impact']}): {v['help']} — "
        + "; ".join(n["target"][0] for n in v["nodes"][:3])
        for v in page.evaluate("async () => (await axe.run(document)).violations")
        if v["impact"] in ("serious", "critical")
    ]
