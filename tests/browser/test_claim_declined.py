"""*Not yet* to the lab robot's claim offer holds for that offer in the whole browser
(Debian's Chromium, the queue on the test's `FakeClock`, as in test_queue.py): a reload of
the IDE, and a second tab, keep the dialog closed while the panel still shows the offer's
countdown and its Claim button; a tab whose dialog is open when another tab says *Not yet*
puts it away; a new offer opens the dialog again."""

from __future__ import annotations

import re

import pytest
from playwright.sync_api import Browser, expect

from tests.browser.test_queue import SETTINGS, Lab, ide, join, lab, queue_users
from tests.waiting import wait_until

__all__ = ["lab"]  # the fixture, shared with test_queue.py

pytestmark = pytest.mark.timeout(300)

OFFERED = re.compile(r"the arm is offered: claim it · \d:\d\d$")


def test_not_yet_holds_across_a_reload_and_in_a_second_tab(browser: Browser, lab: Lab) -> None:
    server = lab.start()
    amy, ben = ide(browser, server, "amy"), ide(browser, server, "ben")
    second = amy.context.new_page()  # amy's second tab, open before the offer
    try:
        second.goto(server.url + "/")
        second.wait_for_function("() => window.melfa && window.melfa.queue?.queue")
        join(amy)  # the queue was empty: the arm is offered to her at once
        dialog = amy.page.locator("#claim-dialog")
        expect(dialog).to_have_attribute("open", "")
        expect(second.locator("#claim-dialog")).to_have_attribute("open", "")
        amy.page.click("#claim-later")
        expect(dialog).not_to_have_attribute("open", "")
        # The tab that still showed it puts it away: one answer for the offer.
        expect(second.locator("#claim-dialog")).not_to_have_attribute("open", "")

        amy.open()  # a reload: the same offer, still declined
        wait_until(lambda: queue_users(amy) == ["amy"], what="amy's queue after the reload")
        dialog = amy.page.locator("#claim-dialog")
        expect(dialog).not_to_have_attribute("open", "")
        when = amy.page.locator("#queue-list li[data-user=amy] .queue-when")
        expect(when).to_contain_text(OFFERED)  # the offer's countdown stays
        expect(amy.page.locator("#queue-claim")).to_have_text("Claim the arm and run")
        amy.screenshot("queue-not-yet-reloaded", toasts=False)

        third = amy.context.new_page()  # a tab opened after Not yet
        third.goto(server.url + "/")
        third.wait_for_function("() => window.melfa && window.melfa.queue?.queue")
        expect(third.locator("#queue-claim")).to_be_visible()
        expect(third.locator("#claim-dialog")).not_to_have_attribute("open", "")
        third.close()

        # Her window runs out, ben's too: a new offer opens the dialog again.
        join(ben)
        wait_until(lambda: queue_users(amy) == ["amy", "ben"], what="ben in amy's list")
        lab.advance(SETTINGS.claim_s + 1)
        wait_until(lambda: queue_users(amy) == ["ben", "amy"], what="amy moved back")
        lab.advance(SETTINGS.claim_s + 1)
        wait_until(lambda: queue_users(amy) == ["amy", "ben"], what="ben moved back")
        expect(dialog).to_have_attribute("open", "")
        amy.page.click("#claim-go")
        expect(amy.page.locator("#lease-text")).to_contain_text("you")
    finally:
        second.close()
        amy.close()
        ben.close()
