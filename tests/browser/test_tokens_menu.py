"""The user menu's access tokens: make one (shown once), see it listed, use it, revoke it."""

from __future__ import annotations

import json
import urllib.error
import urllib.request
from typing import Any


def whoami(url: str, token: str) -> int:
    request = urllib.request.Request(
        url + "/api/session", headers={"Authorization": f"Bearer {token}"}
    )
    try:
        with urllib.request.urlopen(request, timeout=30) as reply:
            assert json.loads(reply.read())["user"]["username"] == "bob"
            return int(reply.status)
    except urllib.error.HTTPError as err:
        return int(err.code)


def test_tokens_are_made_listed_and_revoked_in_the_user_menu(open_session: Any) -> None:
    ide = open_session("bob")
    page = ide.page
    for close in page.locator("#toasts .close").all():  # the welcome guide, if shown
        close.click()
    page.click("#user-button")
    page.click("#tokens-open")
    page.wait_for_selector("#tokens-dialog[open]")
    page.fill("#token-label", "thesis page")
    page.click("#token-form button[type=submit]")
    page.wait_for_selector("#token-made:not([hidden])")
    token = page.input_value("#token-value")
    assert token.startswith("melfa_pat_")
    page.wait_for_selector("#tokens-list tr:has-text('thesis page')")
    ide.screenshot("tokens-dialog")
    assert whoami(ide.server.url, token) == 200

    page.click("#tokens-list button[aria-label='Revoke the token thesis page']")
    page.wait_for_selector("#tokens-list td:has-text('No tokens yet.')")
    assert whoami(ide.server.url, token) == 401
