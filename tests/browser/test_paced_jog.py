"""Jog on the real arm's line: `melfa serve` against a virtual controller paced like a
9600-baud 8E2 link (`melfa sim --tcp`). While a key is held the state keeps flowing (the
service polls between jog renewals), and every view says "jogging"."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Browser, expect

from tests.browser.conftest import (
    ADMIN_PASSWORD,
    Server,
    Session,
    melfa_serve,
)
from tests.serving import free_port, stop_process
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(180)


@pytest.fixture(scope="module")
def paced(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("melfa-paced")
    sim_port = free_port()
    sim_log = data / "sim.log"
    command = [sys.executable, "-m", "melfa", "sim", "--tcp", f"127.0.0.1:{sim_port}"]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}  # its "listening" line reaches the log now
    with sim_log.open("w") as log:
        sim = subprocess.Popen(
            [*command, "--baud", "9600"], stdout=log, stderr=subprocess.STDOUT, env=env
        )
        try:
            wait_until(lambda: "listening on" in sim_log.read_text(), 60, "melfa sim to listen")
            robot = f"tcp://127.0.0.1:{sim_port}"
            with melfa_serve(data, "--robot", robot) as url:
                yield Server(url, data, {"admin": ADMIN_PASSWORD})
        finally:
            stop_process(sim)


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
