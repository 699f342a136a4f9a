"""The running line in the editor follows the numbering that was really sent: a program
numbered by its tokens (``3END`` is step 3) runs as steps 1, 2, 3 and the editor marks
those lines (the upload used to renumber it 10, 20, 30 while the IDE mapped 1, 2, 3)."""

from __future__ import annotations

from typing import Any

import pytest
from playwright.sync_api import expect

from tests.browser.conftest import Server, Session, free_the_robot
from tests.waiting import wait_until

pytestmark = pytest.mark.timeout(120)

PROGRAM = "1 MOV P1\n2 GOTO 1\n3END"
POINTS = "DEF POS P1=(400.00,0.00,400.00,180.00,0.00,180.00)(7,0)\n"


def test_a_program_numbered_by_its_tokens_shows_its_running_line(
    open_session: Any, server: Server, stop_robot: None
) -> None:
    s: Session = open_session("bob")
    page = s.page
    free_the_robot(page, server)
    s.set_points(POINTS)
    s.set_program(PROGRAM)
    page.click("#act-load")
    expect(page.locator(".toast", has_text="Project loaded")).to_be_visible(timeout=30_000)
    page.click("#act-run")
    page.locator(".toast.error").get_by_role("button", name="Turn on and retry").click()
    seen: set[str] = set()

    def marked() -> bool:
        seen.add(page.get_attribute("#editor", "data-run-line") or "")
        return bool(seen & {"1", "2"})

    wait_until(marked, what="the editor to mark the running line")
    page.click("#estop")
