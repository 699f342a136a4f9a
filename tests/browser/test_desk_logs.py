"""The instructor's desk reads what happened to each robot from the server (issue 26), in
Debian's Chromium: the lab robot's log (who took control, what they did, who gave it back)
and a student's own simulator's, apart; the audit log with control changes in plain words
and a Robot column, a refused take among the control changes and a refused queue claim
among the queue's entries; the old /audit page leads to it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from melfa.vocab.queue import QueueStep
from melfa.vocab.refusals import Refusal
from tests.browser.conftest import Server, Session, free_the_robot

pytestmark = pytest.mark.timeout(300)
LEASE_TEXT = Refusal.LEASE_REQUIRED.words(holder="tove")[0]


def _as(page: Page, server: Server, user: str) -> Any:
    """A second browser context signed in as ``user``: its request API and CSRF header."""
    other = page.context.browser.new_context()  # type: ignore[union-attr]
    reply = other.request.post(
        server.url + "/api/session", data={"username": user, "password": server.passwords[user]}
    )
    return other, {"X-CSRF-Token": reply.json()["csrf_token"]}


def test_each_robot_s_log_and_the_audit_log_on_the_desk(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    server.add_user("sven", role="instructor")
    server.add_user("tove")
    server.add_user("ulla")
    sven: Session = open_session("sven", login=False)
    sven.login_api()
    page = sven.page
    free_the_robot(page, server)
    tove, csrf = _as(page, server, "tove")
    ulla, ulla_csrf = _as(page, server, "ulla")
    try:
        assert tove.request.post(server.url + "/api/lease", headers=csrf).ok
        taken = ulla.request.post(server.url + "/api/lease", headers=ulla_csrf)
        assert taken.status == 423  # tove holds it: refused, and audited
        assert tove.request.post(server.url + "/api/robot/stop", headers=csrf).ok
        assert tove.request.delete(server.url + "/api/lease", headers=csrf).ok
        claim = tove.request.post(server.url + "/api/queue/claim", headers=csrf, data={})
        assert claim.status == 409  # not offered to her: refused, and audited
        mine = tove.request.post(server.url + "/api/robot/stop?target=mine", headers=csrf)
        assert mine.ok
    finally:
        tove.close()
        ulla.close()

    page.goto(server.url + "/audit")  # the old page leads to the desk's audit log
    page.wait_for_selector("body[data-ready=true]")
    expect(page.locator("#audit-pane")).to_be_visible()
    page.select_option("#audit-kind", "control")
    took = page.locator("#audit-rows tr", has_text="tove took control")
    expect(took.first).to_be_visible()
    expect(took.first).to_contain_text("Lab robot")
    expect(page.locator("#audit-rows tr", has_text="tove gave control back").first).to_be_visible()
    assert "control.changed" not in page.locator("#audit-rows").inner_text()
    refused = page.locator("#audit-rows tr", has_text="Take control").filter(has_text="ulla")
    expect(refused.first).to_contain_text(LEASE_TEXT)  # a refused take is a control change too
    page.select_option("#audit-kind", "queue")  # her refused claim is among the queue's
    claimed = page.locator("#audit-rows tr", has_text="Claim the arm").filter(has_text="tove")
    expect(claimed.first).to_contain_text("The arm is not offered to you yet.")
    sven.screenshot("desk-audit-queue")
    # A queue step is said in the vocabulary's words, from its code and facts, not in the
    # sentence the server stored with it
    said = page.evaluate(
        """async () => (await import('/static/js/desk-audit.js')).said({action: 'queue.missed',
             details: {user: 'tove', words: 'written by the server'}})"""
    )
    assert said == QueueStep.MISSED.words(user="tove")
    page.select_option("#audit-kind", "all")
    with page.expect_download() as download:
        page.click("#audit-csv")
    text = Path(download.value.path()).read_text(encoding="utf-8")
    assert text.startswith("When,Who,Robot,What,Result\n") and "tove took control" in text

    page.click("#tab-robots")
    rows = page.locator("#robots-rows tr")
    expect(page.locator("#robots-pick")).to_have_value("lab")
    expect(rows.filter(has_text="tove took control").first).to_be_visible()
    stops = rows.filter(has_text="tove").filter(has_text="Stop")
    expect(stops.first).to_be_visible()
    assert "{" not in page.locator("#robots-rows").inner_text()  # words, never JSON
    sven.screenshot("desk-robot-log")

    page.select_option("#robots-pick", "sim:tove")  # her own simulator's log, apart
    expect(rows.filter(has_text="tove").first).to_be_visible()
    expect(rows.filter(has_text="took control")).to_have_count(0)
    assert all(r.split("\t")[1] in ("tove", "melfa") for r in rows.all_inner_texts())
