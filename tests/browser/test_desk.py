"""The instructor's desk in Debian's Chromium at 1366×768 (issue 26's "Done when"): an
instructor imports a class list, reads the passwords shown once, resets a student's
password (the student signs in with it), removes an account, and toggles the simulation
gate (a student's pre-flight settings follow at once; the card says who set it and that a
restart keeps it). Screenshots for docs/ide.md."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from tests.browser.conftest import Server, Session, axe_serious

pytestmark = pytest.mark.timeout(300)

HASHING = 30_000  # ms: three Argon2 hashes on a loaded shared machine

CLASS_LIST = "username,name,group\ndorothy,Dora Diaz,G3\nelias,Eli Ek,G3\nfayola,Fay Fox,G4\n"
# Names no other browser test module gives an account: they share one server.


def _signs_in(page: Page, server: Server, user: str, password: str) -> bool:
    other = page.context.browser.new_context()  # type: ignore[union-attr]
    try:
        reply = other.request.post(
            server.url + "/api/session", data={"username": user, "password": password}
        )
        return reply.ok
    finally:
        other.close()


def _desk_axe(page: Page) -> list[str]:
    return [p for p in axe_serious(page) if any(k in p for k in ("acc-", "gate-", "once-", "desk"))]


def test_an_instructor_manages_accounts_from_the_desk(
    open_session: Any, server: Server, tmp_path: Path
) -> None:
    server.add_user("mia", role="instructor")
    mia: Session = open_session("mia")
    page = mia.open_page("/desk")
    rows = page.locator("#acc-rows tr")
    expect(page.locator("#acc-rows tr[data-user=alice]")).to_be_visible()
    expect(page.locator("#acc-rows tr[data-user=admin]")).to_have_count(0)  # staff: admins'
    expect(page.locator("#acc-note")).to_contain_text("you manage students")

    # A list with a problem imports nothing and says where, in the desk's words
    bad_list = tmp_path / "bad.csv"
    bad_list.write_text("username,name,group\nzed,Zed Z,G3\nzed,Zed Y,G3\n", encoding="utf-8")
    page.click("#acc-import")
    page.set_input_files("#import-file", str(bad_list))
    page.click("#import-ok")
    expect(page.locator("#import-problems li").nth(1)).to_have_text(
        "line 3: 'zed' is already on line 2", timeout=HASHING
    )

    class_list = tmp_path / "class.csv"
    class_list.write_text(CLASS_LIST, encoding="utf-8")
    page.set_input_files("#import-file", str(class_list))
    page.click("#import-ok")
    once = page.locator("#once-dialog")
    expect(once).to_be_visible(timeout=HASHING)
    expect(once.locator("tbody tr")).to_have_count(3)
    dora_first = once.locator("tbody tr", has_text="dorothy").locator("td").nth(1).inner_text()
    mia.screenshot("desk-imported", toasts=False)
    assert _desk_axe(page) == []
    once.get_by_role("button", name="Done").click()
    expect(page.locator("#acc-rows tr[data-user=fayola]")).to_contain_text("G4")
    assert _signs_in(page, server, "dorothy", dora_first)

    page.locator("#acc-rows tr[data-user=dorothy] [data-act=reset]").click()
    expect(page.locator("#confirm-text")).to_contain_text("Give dorothy a new password?")
    page.click("#confirm-ok")
    expect(once).to_be_visible(timeout=HASHING)
    expect(once.locator("tbody tr")).to_have_count(1)
    new_password = once.locator(".desk-password").inner_text()
    assert new_password != dora_first
    once.get_by_role("button", name="Done").click()
    assert _signs_in(page, server, "dorothy", new_password)
    assert not _signs_in(page, server, "dorothy", dora_first)

    before = rows.count()
    page.locator("#acc-rows tr[data-user=fayola] [data-act=remove]").click()
    page.click("#confirm-ok")
    expect(rows).to_have_count(before - 1)
    expect(page.locator("#acc-rows tr[data-user=fayola]")).to_have_count(0)

    page.fill("#acc-find", "G3")
    expect(rows).to_have_count(2)
    page.fill("#acc-find", "")
    mia.screenshot("desk-accounts", toasts=False)


def test_an_instructor_toggles_the_gate_live(open_session: Any, server: Server) -> None:
    server.add_user("noa", role="instructor")
    noa: Session = open_session("noa")
    page = noa.open_page("/desk")
    alice: Session = open_session("alice")

    def required() -> bool:
        reply = alice.page.request.get(server.url + "/api/preflight")
        return bool(reply.json()["require_simulation"])

    toggle = page.locator("#gate-toggle")
    expect(toggle).to_have_attribute("aria-pressed", "false")
    assert required() is False
    toggle.click()
    expect(toggle).to_have_attribute("aria-pressed", "true")
    expect(page.locator("#gate-state")).to_contain_text("must pass pre-flight")
    # Where it came from, in plain words: saved, so a restart keeps it.
    expect(page.locator("#gate-from")).to_contain_text("Set by noa on the desk")
    expect(page.locator("#gate-from")).to_contain_text("A restart keeps it.")
    assert required() is True
    noa.screenshot("desk-gate-on", toasts=False)
    toggle.click()
    expect(toggle).to_have_attribute("aria-pressed", "false")
    assert required() is False


def test_an_instructors_stop_holds_until_released(open_session: Any, server: Server) -> None:
    server.add_user("ola", role="instructor")
    ola: Session = open_session("ola")
    page = ola.open_page("/desk")
    alice: Session = open_session("alice")
    hold = page.locator("#hold-toggle")
    expect(hold).to_have_attribute("aria-pressed", "false")
    hold.click()
    expect(hold).to_have_attribute("aria-pressed", "true")
    expect(page.locator("#hold-state")).to_contain_text("Held by ola")
    ola.screenshot("desk-held", toasts=False)
    try:
        alice.page.click("#act-load")  # the student is told who stopped it
        expect(alice.page.locator(".toast").last).to_contain_text(
            "ola stopped the robot and is holding it"
        )
        page.click("#reset-alarm")  # from the staff side, without taking over
        expect(page.locator(".toast").last).to_contain_text("The alarm was reset")
    finally:
        hold.click()
    expect(hold).to_have_attribute("aria-pressed", "false")
    reply = alice.page.request.post(
        server.url + "/api/robot/run",
        headers={
            "X-CSRF-Token": str(alice.eval("() => document.cookie.match(/melfa_csrf=([^;]+)/)[1]"))
        },
    )
    assert reply.status != 423 or reply.json()["error"]["code"] != "held"


def test_an_instructor_reads_the_audit_log(open_session: Any, server: Server) -> None:
    server.add_user("pia", role="instructor")
    pia: Session = open_session("pia")
    page = pia.open_page("/desk")
    alice: Session = open_session("alice")
    page.click("#gate-toggle")
    expect(page.locator("#gate-toggle")).to_have_attribute("aria-pressed", "true")
    try:
        alice.page.click("#act-load")  # refused by the gate: audited as a refusal
        expect(alice.page.locator(".toast").last).to_contain_text("pre-flight")
    finally:
        page.click("#gate-toggle")
    expect(page.locator("#gate-toggle")).to_have_attribute("aria-pressed", "false")
    page.click("#tab-audit")
    rows = page.locator("#audit-rows tr")
    expect(rows.first).to_be_visible()
    gate_on = page.locator("#audit-rows tr", has_text="turned the simulation gate on")
    expect(gate_on.filter(has_text="pia")).to_have_count(1)  # others' tests switch it too
    expect(page.locator("#audit-rows tr", has_text="signed in").first).to_be_visible()
    refused = page.locator("#audit-rows tr.refused", has_text="Load project")
    expect(refused.first).to_contain_text("alice")
    assert "{" not in page.locator("#audit-rows").inner_text()  # plain words, no JSON
    # One row per robot command: an accepted entry with its outcome reads once.
    entries = page.request.get(server.url + "/api/audit?limit=500").json()["entries"]
    robot = [e for e in entries if e["action"].startswith("robot.")]
    ended = {e["details"]["command_id"] for e in robot if e["result"] != "accepted"}
    pairs = sum(
        1 for e in robot if e["result"] == "accepted" and e["details"]["command_id"] in ended
    )
    page.select_option("#audit-kind", "robot")
    expect(page.locator("#audit-rows tr")).to_have_count(len(robot) - pairs)
    page.select_option("#audit-kind", "all")
    page.fill("#audit-who", "alice")
    page.press("#audit-who", "Enter")
    expect(page.locator("#audit-rows tr", has_text="pia")).to_have_count(0)
    with page.expect_download() as download:
        page.click("#audit-csv")
    text = Path(download.value.path()).read_text(encoding="utf-8")
    assert text.startswith("When,Who,Robot,What,Result\n") and "alice" in text
    page.fill("#audit-who", "")
    page.press("#audit-who", "Enter")
    expect(page.locator("#audit-rows tr", has_text="pia").first).to_be_visible()
    pia.screenshot("desk-audit", toasts=False)
