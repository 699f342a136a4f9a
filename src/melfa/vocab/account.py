"""A signed-in person's own account, in words: the user menu's *Access tokens* and *Change
password* dialogs.

Pure: the browser gets `ACCOUNT_WORDS` through ``/vocab.js`` (``static/js/tokens.js``,
``static/js/password.js``); ``{label}`` is a token's label.
"""

from __future__ import annotations

__all__ = ["ACCOUNT_WORDS"]

ACCOUNT_WORDS: dict[str, str] = {
    "revoke": "Revoke",
    "revoke-label": "Revoke the token {label}",
    "no-tokens": "No tokens yet.",
    "list-failed": "Could not list your tokens",
    "make-failed": "Could not make a token",
    "revoked": "Token “{label}” revoked",
    "revoke-failed": "Could not revoke the token",
    "password-changed": "Password changed; your other sessions were signed out",
    "password-failed": "Could not change the password",
}
