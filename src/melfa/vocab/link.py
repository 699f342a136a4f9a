"""The line to the controller, as the service sees it, and the student's words for it.

Pure: the service reports `LinkStatus`; the header, the desktop client's status bar and
the ``link`` message show `LINK_WORDS` of it.
"""

from __future__ import annotations

import enum


class LinkStatus(enum.StrEnum):
    """State of the line to the controller."""

    CONNECTING = "connecting"
    CONNECTED = "connected"
    RECONNECTING = "reconnecting"
    LOST = "lost"
    """Reconnecting for longer than `ServiceConfig.lost_after_s`; still trying."""
    CLOSED = "closed"


LINK_WORDS: dict[LinkStatus, str] = {
    LinkStatus.CONNECTED: "Robot connected",
    LinkStatus.CONNECTING: "Connecting to the robot…",
    LinkStatus.RECONNECTING: "Robot link lost; reconnecting…",
    LinkStatus.LOST: "Robot link lost",
    LinkStatus.CLOSED: "Robot link closed",
}


LINK_UNKNOWN = "Robot link unknown"
"""Before the server has said how the link is (or a state this client does not know)."""


__all__ = ["LINK_UNKNOWN", "LINK_WORDS", "LinkStatus"]
