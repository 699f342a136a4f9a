"""The lab robot's queue in Debian's Chromium, on a real uvicorn in this process so the test
owns the queue's clock (a `FakeClock` it moves on itself: no sleep waits for a claim window
or a turn): three students pass pre-flight and queue; everyone sees the places and
estimates; the head's claim gives them the arm and runs their text with nobody else's
click; a missed claim moves back one place; a turn ends on time and hands over; an
unsimulated text cannot enter; attended mode waits for the supervisor's click; the
instructor reorders and skips; a restart keeps the queue."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, expect

from melfa.service.clock import FakeClock
from melfa.service.queue import QueueSettings
from melfa.web import WebSettings
from tests.browser.conftest import Server, Session
from tests.waiting import wait_until
from tests.web.conftest import PASSWORDS, fast_service, make_store
from tests.web.live_server import Live, live_server

pytestmark = pytest.mark.timeout(300)

PROGRAM = "' {who}\nSERVO ON\nMOV P1\nEND\n"
POINTS = "DEF POS P1=(350.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
UNREACHABLE = "DEF POS P1=(2500.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"
STUDENTS = ("amy", "ben", "cyd")
PASSWORD = "student-password-1"
SETTINGS = QueueSettings(claim_s=60, turn_s=240, warn_s=30, grace_s=600)


class Lab:
    """A served melfa whose queue runs on ``clock``; restartable on the same database."""

    def __init__(self, data: Path) -> None:
        self.data = data
        self.clock = FakeClock(start=time.time())
        self.settings = WebSettings(
            data_dir=data,
            service_config=fast_service(),
            require_simulation=True,
            queue=SETTINGS,
        )
        self._serving: Any = None
        self.live: Live | None = None
        self.store: Any = None

    def start(self) -> Server:
        self.store = make_store(self.data)
        for user in STUDENTS:  # no group: each edits their own workspace
            if self.store.accounts.find_user(user) is None:
                self.store.accounts.create_user(user, PASSWORD)
        self._serving = live_server(self.store, self.settings, queue_clock=self.clock)
        self.live = self._serving.__enter__()
        return Server(self.live.url, self.data, {**PASSWORDS, **dict.fromkeys(STUDENTS, PASSWORD)})

    def stop(self) -> None:
        if self._serving is not None:
            self._serving.__exit__(None, None, None)
            self.store.close()
            self._serving = None

    def advance(self, seconds: float) -> None:
        self.clock.advance_to(self.clock.now() + seconds)


@pytest.fixture
def lab(tmp_path: Path) -> Iterator[Lab]:
    lab = Lab(tmp_path / "data")
    try:
        yield lab
    finally:
        lab.stop()


def ide(browser: Browser, server: Server, user: str) -> Session:
    session = Session(browser, server, user)
    session.login_api()
    session.eval("() => document.getElementById('toasts').replaceChildren()")
    return session


def queue_users(s: Session) -> list[str]:
    return list(
        s.eval("() => [...document.querySelectorAll('#queue-list li')].map(li => li.dataset.user)")
    )


def join(s: Session, points: str = POINTS) -> None:
    s.set_program(PROGRAM.format(who=s.user))
    s.set_points(points)
    s.page.click("#queue-join")


def test_three_students_queue_claim_miss_hand_over_and_restart(browser: Browser, lab: Lab) -> None:
    server = lab.start()
    amy, ben, cyd, ivy = (ide(browser, server, u) for u in ("amy", "ben", "cyd", "ivy"))
    sessions = [amy, ben, cyd, ivy]
    try:
        # An unsimulated text cannot enter: pre-flight finds an error, nothing is queued
        join(cyd, UNREACHABLE)
        expect(cyd.page.locator("#preflight")).to_have_attribute("data-passed", "false")
        expect(cyd.page.locator(".toast.error").first).to_contain_text("Could not join the queue")
        assert queue_users(cyd) == []

        # Three students pass pre-flight and queue (the button runs it when the lab asks)
        for s in (amy, ben, cyd):
            join(s)
            expect(s.page.locator("#queue-list li.mine")).to_have_count(1)
        for s in sessions:  # everyone sees the same places, live
            wait_until(lambda s=s: queue_users(s) == ["amy", "ben", "cyd"], what=f"{s.user}'s list")
        expect(ben.page.locator("#queue-list li[data-user=cyd] .queue-when")).to_contain_text(
            "in ≈"
        )
        expect(amy.page.locator("#queue-list li[data-user=amy]")).to_have_class(
            "queue-entry mine offered"
        )

        # The head is offered the arm: a dialog she cannot miss; her claim gives her the arm
        dialog = amy.page.locator("#claim-dialog")
        expect(dialog).to_have_attribute("open", "")
        amy.screenshot("queue-claim")
        amy.page.click("#claim-go")
        expect(amy.page.locator("#lease-text")).to_contain_text("you")
        expect(ben.page.locator("#queue-turn")).to_have_attribute("data-user", "amy")
        wait_until(lambda: runs(lab) == ["amy"], what="amy's program run")
        assert queue_users(ben) == ["ben", "cyd"]
        ben.screenshot("queue")

        # The turn ends on time and hands over: ben is offered the arm
        lab.advance(SETTINGS.turn_s + 1)
        expect(ben.page.locator("#claim-dialog")).to_have_attribute("open", "")
        expect(amy.page.locator("#lease-text")).not_to_contain_text("you")
        expect(amy.page.locator("#queue-turn")).to_have_count(0)

        # ben lets the claim window run out: he moves back one place, not out; cyd is offered
        lab.advance(SETTINGS.claim_s + 1)
        wait_until(lambda: queue_users(amy) == ["cyd", "ben"], what="ben moved back one place")
        expect(ben.page.locator("#claim-dialog")).not_to_have_attribute("open", "")
        expect(cyd.page.locator("#claim-dialog")).to_have_attribute("open", "")

        # The instructor reorders (ben up to first) and skips cyd
        ivy.page.click("#queue-list li[data-user=ben] button[aria-label='Move ben up']")
        wait_until(lambda: queue_users(cyd) == ["ben", "cyd"], what="ben moved up")
        ivy.page.click("#queue-list li[data-user=cyd] button:text('Skip')")
        wait_until(lambda: queue_users(ben) == ["ben"], what="cyd skipped")
        ivy.screenshot("queue-instructor")

        # A restart keeps the queue
        for s in sessions:
            s.close()
        sessions = []
        lab.stop()
        server = lab.start()
        ben = ide(browser, server, "ben")
        sessions = [ben]
        wait_until(lambda: queue_users(ben) == ["ben"], what="the queue after a restart")
        expect(ben.page.locator("#claim-dialog")).to_have_attribute("open", "")
    finally:
        for s in sessions:
            s.close()


def test_attended_mode_waits_for_the_supervisors_click(browser: Browser, lab: Lab) -> None:
    server = lab.start()
    amy, ivy = ide(browser, server, "amy"), ide(browser, server, "ivy")
    try:
        ivy.page.check("#queue-attended")
        expect(amy.page.locator("#queue .pill", has_text="attended")).to_have_count(1)
        join(amy)
        expect(amy.page.locator("#claim-dialog")).to_have_attribute("open", "")
        amy.page.click("#claim-go")
        expect(ivy.page.locator("#queue-run-waiting")).to_be_visible()
        expect(ivy.page.locator("#queue-ready")).to_have_class("btn btn-sm btn-primary attention")
        lab.advance(20)
        assert runs(lab) == []  # it waits, however long
        ivy.page.click("#queue-ready")
        wait_until(lambda: runs(lab) == ["amy"], what="the run after Arm ready")
        expect(amy.page.locator("#queue-run-waiting")).to_have_count(0)
    finally:
        amy.close()
        ivy.close()


def runs(lab: Lab) -> list[str]:
    """Who started a program on the arm (the audit's runs the controller answered)."""
    lab.store.db.flush()
    entries = lab.store.audit.query(action="robot.run", limit=50).entries
    return [str(e.actor) for e in entries if e.result == "ok"]


def test_a_claim_from_my_simulator_turns_the_ide_to_the_lab_robot_and_stop_reaches_it(
    browser: Browser, lab: Lab
) -> None:
    """A student debugs on My simulator and queues from there (the queue's button sits in
    the simulator's side panel too): claiming runs their program on the lab robot, so the
    IDE shows the lab robot, and the big STOP pressed back on My simulator during the turn
    still stops the lab robot (it used to stop the private simulator only). The chip says
    the program in the slot is the editor's (it said the editor had changed since)."""
    server = lab.start()
    amy = ide(browser, server, "amy")
    try:
        amy.page.click("#target-switch [data-target=mine]")
        amy.wait_ready()
        join(amy)
        expect(amy.page.locator("#claim-dialog")).to_have_attribute("open", "")
        amy.page.click("#claim-go")
        expect(amy.page.locator("body")).to_have_attribute("data-target", "lab")
        expect(amy.page.locator(".view-head h2")).to_have_text("Lab RV-6S")
        expect(amy.page.locator("#lease-text")).to_contain_text("you")
        wait_until(lambda: runs(lab) == ["amy"], what="amy's program run")
        # The claim loaded her editor's text, not this page: still, it is hers, unchanged
        expect(amy.page.locator("#slot-info")).to_have_attribute("data-owner", "mine")

        amy.page.click("#target-switch [data-target=mine]")
        amy.wait_ready()
        # The tab says which robot the page drives (the queue's title blink put the lab's
        # name back on every tick, a page started on the lab robot said "Lab RV-6S" here)
        expect(amy.page).to_have_title(re.compile("My simulator"))
        amy.page.click("#estop")
        wait_until(lambda: "lab" in stops(lab, "amy"), what="amy's STOP on the lab robot")
    finally:
        amy.close()


def stops(lab: Lab, user: str) -> set[str]:
    """Which robots ``user``'s STOPs reached: "lab", "private" (the audit's session)."""
    lab.store.db.flush()
    entries = lab.store.audit.query(action="robot.stop", limit=50).entries
    return {
        "private" if (e.details or {}).get("session") == "private" else "lab"
        for e in entries
        if e.actor == user
    }


def test_the_claim_countdown_runs_in_everyones_list(browser: Browser, lab: Lab) -> None:
    """The list's "the arm is offered: claim it · 0:59" counts down each second for
    everyone (it stood at the value of the last queue message). The browser's clock is
    Playwright's, moved on by the test: nothing waits for time to pass."""
    server = lab.start()
    ben = Session(browser, server, "ben")
    ben.page.clock.install()
    ben.login_api()
    amy = ide(browser, server, "amy")
    try:
        join(amy)  # the queue was empty: the arm is offered to her at once
        when = ben.page.locator("#queue-list li[data-user=amy] .queue-when")
        expect(when).to_contain_text("the arm is offered")

        def seconds() -> int:
            found = re.search(r"(\d+):(\d\d)$", when.inner_text())
            assert found, when.inner_text()
            return int(found[1]) * 60 + int(found[2])

        before = seconds()
        ben.page.clock.run_for(20_000)
        assert seconds() <= before - 19
    finally:
        amy.close()
        ben.close()


def test_while_anyone_waits_the_header_offers_no_take_control(browser: Browser, lab: Lab) -> None:
    """While anyone waits only the queue gives control, so the header's *Take control*
    (which the service would refuse) goes and it says control is given by the queue; it
    comes back when the queue is empty."""
    server = lab.start()
    amy, ben = ide(browser, server, "amy"), ide(browser, server, "ben")
    try:
        expect(ben.page.locator("#lease-take")).to_be_visible()
        join(amy)
        expect(amy.page.locator("#claim-dialog")).to_have_attribute("open", "")
        for s in (amy, ben):
            expect(s.page.locator("#lease-take")).to_be_hidden()
            expect(s.page.locator("#lease-text")).to_contain_text("by the queue")
        amy.page.click("#claim-later")
        amy.page.click("#queue-leave")
        expect(ben.page.locator("#lease-take")).to_be_visible()
        expect(ben.page.locator("#lease-text")).to_contain_text("free")
    finally:
        amy.close()
        ben.close()


def test_not_yet_keeps_the_claim_dialog_closed_for_that_offer(browser: Browser, lab: Lab) -> None:
    """*Not yet* (or Esc) puts the claim dialog away for the offer it was said to: the
    queue's next updates do not open it again (they did, each time). The panel still shows
    the offer with its countdown and a *Claim the arm and run*; a new offer opens the dialog
    again."""
    server = lab.start()
    amy, ben = ide(browser, server, "amy"), ide(browser, server, "ben")
    dialog = amy.page.locator("#claim-dialog")
    claim = amy.page.locator("#queue-claim")
    try:
        join(amy)  # the queue was empty: the arm is offered to her at once
        expect(dialog).to_have_attribute("open", "")
        amy.page.click("#claim-later")
        expect(dialog).not_to_have_attribute("open", "")

        join(ben)  # the queue changes under her: the same offer, still declined
        wait_until(lambda: queue_users(amy) == ["amy", "ben"], what="ben in amy's list")
        expect(dialog).not_to_have_attribute("open", "")
        when = amy.page.locator("#queue-list li[data-user=amy] .queue-when")
        expect(when).to_contain_text(re.compile(r"the arm is offered: claim it · \d:\d\d$"))
        expect(claim).to_have_text("Claim the arm and run")
        amy.screenshot("queue-not-yet", toasts=False)

        # Her window runs out: she moves back one place, ben is offered; then his does
        lab.advance(SETTINGS.claim_s + 1)
        wait_until(lambda: queue_users(amy) == ["ben", "amy"], what="amy moved back")
        expect(claim).to_have_count(0)
        expect(ben.page.locator("#claim-dialog")).to_have_attribute("open", "")
        lab.advance(SETTINGS.claim_s + 1)
        wait_until(lambda: queue_users(amy) == ["amy", "ben"], what="ben moved back")

        # A new offer: the dialog again; Esc declines it as Not yet does
        expect(dialog).to_have_attribute("open", "")
        amy.page.keyboard.press("Escape")
        expect(dialog).not_to_have_attribute("open", "")
        ben.page.click("#queue-leave")
        wait_until(lambda: queue_users(amy) == ["amy"], what="ben out of amy's list")
        expect(dialog).not_to_have_attribute("open", "")

        # The panel's Claim does what the dialog's does
        claim.click()
        expect(amy.page.locator("#lease-text")).to_contain_text("you")
        wait_until(lambda: runs(lab) == ["amy"], what="amy's program run")
        expect(claim).to_have_count(0)
    finally:
        amy.close()
        ben.close()
