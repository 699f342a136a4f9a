"""Jog on the real arm's line: `melfa serve` against a virtual controller paced like a
9600-baud 8E2 link (`melfa sim --tcp`). While a key is held the state keeps flowing (the
service polls between jog renewals), and every view says "jogging"."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Browser, expect

from tests.browser.conftest import ADMIN_PASSWORD, Server, Session

pytestmark = pytest.mark.timeout(180)


def _port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def paced(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("melfa-paced")
    sim_port, web_port = _port(), _port()
    env = {k: v for k, v in os.environ.items() if k != "MELFA_ROBOT"}
    env["MELFA_ADMIN_PASSWORD"] = ADMIN_PASSWORD
    log = (data / "serve.log").open("w")
    sim = subprocess.Popen(
        [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{sim_port}", "--baud", "9600"],
        stdout=log,
        stderr=subprocess.STDOUT,
        env=env,
    )
    time.sleep(1.0)
    serve = subprocess.Popen(
        [
            *(sys.executable, "-m", "melfa", "serve", "--port", str(web_port)),
            *("--data", str(data), "--robot", f"tcp://127.0.0.1:{sim_port}"),
        ],
        stdout=log,
        stderr=subprocess.STDOUT,
        env=env,
    )
    url = f"http://127.0.0.1:{web_port}"
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                with urllib.request.urlopen(url + "/api/health", timeout=2) as reply:
                    if json.loads(reply.read())["robot"]["link"] == "connected":
                        break
            except OSError:
                pass
            assert time.monotonic() < deadline, (data / "serve.log").read_text()
            time.sleep(0.2)
        server = Server(url, data, {"admin": ADMIN_PASSWORD})
        yield server
    finally:
        for proc in (serve, sim):
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()
        log.close()


def test_jog_state_flows_while_the_key_is_held_on_a_9600_baud_link(
    browser: Browser, paced: Server
) -> None:
    s = Session(browser, paced, "admin")
    try:
        s.login_api()
        page = s.page
        page.click("#tab-robot")
        canvas = page.locator("#jog-canvas")
        canvas.focus()
        page.keyboard.down("w")  # the servo is off: the first press asks
        fix = page.get_by_role("button", name="Turn on and retry")
        expect(fix).to_be_visible(timeout=15_000)
        page.keyboard.up("w")
        fix.click()
        s.eval(
            "() => new Promise((r) => { const t = setInterval(() => "
            "{ if (window.melfa.state.servo) { clearInterval(t); r(); } }, 50); })"
        )
        s.eval(
            "() => { window.__states = []; window.melfa.live.on('state', (m) => "
            "window.__states.push([performance.now(), m.activity, JSON.stringify(m.joints), "
            "m.pose && m.pose[0]])); }"
        )
        canvas.focus()
        page.keyboard.down("w")
        page.wait_for_timeout(600)
        expect(page.locator("#run-state")).to_have_text("jogging")
        expect(canvas).to_have_attribute("data-activity", "Jogging X+ (base)")
        page.wait_for_timeout(1400)
        page.keyboard.up("w")
        page.wait_for_timeout(1500)
        states: list[list[Any]] = s.eval("() => window.__states")
        held = [st for st in states if st[1] == "jogging"]
        readings = [(st[2], st[3]) for st in held]
        xs = [st[3] for st in held if st[3] is not None]
        # Fresh positions keep arriving while held: several different readings, X rising.
        assert len(set(readings)) >= 3, held
        assert xs[-1] > xs[0]
        expect(page.locator("#run-state")).to_have_text("idle")
        s.screenshot("jog-paced")
    finally:
        s.close()
