"""A queued student is told at once when an instructor's edit of the lab's cell cancels
their pass, in Debian's Chromium on a real uvicorn (the queue's clock a `FakeClock` nobody
moves: what the student sees comes from the edit itself, not from a tick or their turn).
Two students pass pre-flight and queue; the instructor saves a new cell in the cell
dialog; ben, second in line, sees his entry marked "must pass pre-flight again" with *Run
pre-flight*, and a toast that says so with the same button; one click passes it in the cell
as it is and updates his queued program, and the mark goes."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from playwright.sync_api import Browser, expect

from melfa.vocab.queue import QUEUE_WORDS, QueueStep
from tests.browser.test_preflight import FAR_FIXTURE, edit_cell
from tests.browser.test_queue import Lab, ide, join, queue_users
from tests.waiting import wait_until


def test_a_queued_student_sees_at_once_that_a_cell_edit_cancelled_their_pass(
    browser: Browser, tmp_path: Path
) -> None:
    lab = Lab(tmp_path / "data")
    sessions: list[Any] = []
    try:
        server = lab.start()
        amy, ben, ivy = (ide(browser, server, u) for u in ("amy", "ben", "ivy"))
        sessions = [amy, ben, ivy]
        for s in (amy, ben):  # the button runs pre-flight when the lab asks for it
            join(s)
            expect(s.page.locator("#queue-list li.mine")).to_have_count(1)
        wait_until(lambda: queue_users(ben) == ["amy", "ben"], what="ben's list")
        mine = ben.page.locator("#queue-list li[data-user=ben]")
        expect(mine.locator("[data-gate]")).to_have_count(0)
        ben.eval("() => document.getElementById('toasts').replaceChildren()")

        edit_cell(ivy, FAR_FIXTURE)  # the instructor adds a fixture

        tag = mine.locator("[data-gate]")
        expect(tag).to_have_text(QUEUE_WORDS.preflight_again)
        expect(tag).to_have_attribute("title", QUEUE_WORDS.preflight_again_hint)
        told = ben.page.locator(".toast", has_text=QueueStep.PREFLIGHT_AGAIN.words(user="ben"))
        expect(told).to_be_visible()
        expect(told.get_by_role("button", name=QUEUE_WORDS.preflight)).to_be_visible()
        others = amy.page.locator("#queue-list li[data-user=ben] [data-gate]")
        expect(others).to_have_text(QUEUE_WORDS.preflight_again)  # everyone sees the mark
        expect(amy.page.locator("#queue-preflight")).to_be_visible()  # amy's own entry too
        expect(ben.page.locator("#preflight")).to_have_attribute("data-may-run", "false")
        ben.screenshot("queue-preflight-again")

        ben.page.click("#queue-preflight")
        expect(ben.page.locator("#preflight")).to_have_attribute("data-may-run", "true")
        expect(mine.locator("[data-gate]")).to_have_count(0)
        expect(ben.page.locator("#queue-preflight")).to_have_count(0)
        expect(amy.page.locator("#queue-list li[data-user=amy] [data-gate]")).to_have_count(1)
    finally:
        for s in sessions:
            s.close()
        lab.stop()  # its server and simulators, not left running for the rest of the suite
        lab.stop()
