"""The IDE under the server's Content-Security-Policy, and changing one's own password from
the user menu, in Debian's Chromium against a real `melfa serve`."""

from __future__ import annotations

from typing import Any

from playwright.sync_api import expect

from tests.browser.conftest import Server, Session


def test_the_ide_runs_under_the_csp_and_changes_a_password(
    open_session: Any, server: Server
) -> None:
    server.add_user("dora")
    carol = open_session("dora")
    violations: list[str] = []
    carol.page.on(
        "console",
        lambda m: violations.append(m.text) if "Content Security Policy" in m.text else None,
    )
    carol.open()
    carol.wait_ready()  # editor, socket and 3D state all up under the policy
    assert violations == []
    page = carol.page
    page.click("#user-button")
    page.click("#password-open")
    page.fill("#password-current", carol.server.passwords["dora"])
    page.fill("#password-new", "password123")
    page.click("#password-form button[type=submit]")
    expect(page.locator("#password-error")).to_contain_text("common")
    page.fill("#password-new", "amber-kettle-orbit")
    page.click("#password-form button[type=submit]")
    # two password hashes (check the old, hash the new) at niceness +10: slow on a busy machine
    expect(page.locator(".toast", has_text="Password changed")).to_be_visible(timeout=30_000)
    carol.server.passwords["dora"] = "amber-kettle-orbit"
    assert isinstance(carol, Session) and carol.errors == []
