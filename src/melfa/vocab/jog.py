"""Why a hold-to-move jog ended: one code per cause, with the student's words.

The service's ``jog`` event carries the code (``end``) and, for the causes a person brings
about, who (``by``: the user who pressed STOP or took control); a refusal carries the
controller's text as its detail. Clients show `JogEnd.words` (the browser from the served
vocabulary), never a parsed sentence.

>>> JogEnd.HEARTBEAT_LOST.words()
"the key's signal stopped reaching the server, so the arm stopped"
>>> JogEnd.STOPPED.words("ann"), JogEnd.TAKEN_OVER.words("iris")
('STOP pressed by ann', 'iris took control')
>>> JogEnd.STOPPED.template
'STOP pressed by {by}'
>>> JogEnd.RELEASED.expected
True
"""

from __future__ import annotations

import enum


class JogEnd(enum.StrEnum):
    """Why a jog ended (stable wire value)."""

    RELEASED = "released"
    """The student let the key go (the normal end: nothing to tell them)."""
    HEARTBEAT_LOST = "heartbeat-lost"
    """The key's heartbeats stopped arriving within `ServiceConfig.jog_heartbeat_timeout_s`."""
    CLIENT_DISCONNECTED = "client-disconnected"
    """The jogging user's last connection closed."""
    LEASE_RELEASED = "lease-released"
    """The jogging user gave control back."""
    LEASE_LOST = "lease-lost"
    """A heartbeat came from a session that no longer holds control."""
    LEASE_ENDED = "lease-ended"
    """Control ended for another reason (idle time out, the service cleared it)."""
    TAKEN_OVER = "taken-over"
    """An instructor took control (``by``: who)."""
    STOPPED = "stopped"
    """Someone pressed STOP (``by``: who)."""
    LINK_DOWN = "link-down"
    """The line to the controller dropped."""
    REFUSED = "refused"
    """The controller refused a JOG (the detail is its message)."""
    SERVICE_CLOSING = "service-closing"
    """The server is shutting down."""

    @property
    def template(self) -> str:
        """The words with ``{by}`` where the person goes (for clients that fill it in)."""
        return _WORDS[self]

    @property
    def expected(self) -> bool:
        """The student ended it themselves: no warning to show."""
        return self is JogEnd.RELEASED

    def words(self, by: str | None = None) -> str:
        """The student's words; ``by`` names the person (STOP, take-over)."""
        text = _WORDS[self]
        if "{by}" in text:
            return (
                text.format(by=by)
                if by
                else text.replace(" by {by}", "").replace("{by} ", "someone ")
            )
        return text


_WORDS: dict[JogEnd, str] = {
    JogEnd.RELEASED: "the key was let go",
    JogEnd.HEARTBEAT_LOST: "the key's signal stopped reaching the server, so the arm stopped",
    JogEnd.CLIENT_DISCONNECTED: "the connection closed, so the arm stopped",
    JogEnd.LEASE_RELEASED: "control was given back",
    JogEnd.LEASE_LOST: "control ended",
    JogEnd.LEASE_ENDED: "control ended",
    JogEnd.TAKEN_OVER: "{by} took control",
    JogEnd.STOPPED: "STOP pressed by {by}",
    JogEnd.LINK_DOWN: "the robot link was lost",
    JogEnd.REFUSED: "the controller refused to jog",
    JogEnd.SERVICE_CLOSING: "the server is shutting down",
}
assert set(_WORDS) == set(JogEnd), "every jog end has its words"


JOG_END_UNKNOWN = "the server ended it"
"""Why a jog ended when the server gave no reason this client knows."""


__all__ = ["JOG_END_UNKNOWN", "JogEnd"]
