"""What the IDE says when someone signs out with edits the server has not got yet (a shared
lab PC must keep no copy of anyone's work, and no edit may be lost on the way).

Pure: the browser gets `SIGN_OUT_WORDS` through ``/vocab.js``; ``{names}`` is the
workspaces whose edits are only in this browser.
"""

from __future__ import annotations

__all__ = ["SIGN_OUT_WORDS"]

SIGN_OUT_WORDS: dict[str, str] = {
    "checking": "Saving your work on the server before you sign out…",
    "title": "Some of your edits are not on the server yet",
    "text": (
        "Your latest edits to {names} are only in this browser: the connection to the "
        "server is down. Wait, and you are signed out as soon as they are saved; sign out "
        "now, and they are thrown away (this computer keeps no copy)."
    ),
    "wait": "Wait, then sign out",
    "waiting": "Waiting for the connection… you are signed out once your edits are saved.",
    "discard": "Sign out and throw them away",
    "stay": "Stay signed in",
}
