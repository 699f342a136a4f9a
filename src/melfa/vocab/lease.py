"""Why control of the robot (the operator lease) changed hands: one code per cause, with
the student's words.

The service's ``lease`` event carries the code (``reason``); clients show `LeaseReason.words`
(the browser from the served vocabulary), never a sentence the server wrote.

>>> LeaseReason.IDLE_TIMEOUT.words()
'control ended after a while with nothing done'
>>> LeaseReason.TAKEN_BY_COMMAND.words("ann", "Move to")
'ann took control by using Move to'
>>> LeaseReason.RELEASED.words()
'someone gave control back'
"""

from __future__ import annotations

import enum


class LeaseReason(enum.StrEnum):
    """Why the lease changed (stable wire value)."""

    ACQUIRED = "acquired"
    """Someone took free control (*Take control*)."""
    TAKEN_BY_COMMAND = "taken-by-command"
    """A command took free control (the event's ``command`` says which)."""
    TAKEN_OVER = "taken-over"
    """An instructor took control from its holder."""
    RELEASED = "released"
    """The holder gave control back."""
    COMMAND_FAILED = "command-failed"
    """The command that took free control failed, so control went back."""
    HOLDER_LEFT_MOVING = "holder-left-moving"
    """The holder's last connection closed while the arm moved: control stays theirs until
    the arm stops (or they come back)."""
    HOLDER_RECONNECTED = "holder-reconnected"
    """The holder came back while the arm still moved for them."""
    HOLDER_DISCONNECTED = "holder-disconnected"
    """The holder's last connection closed while the arm stood still."""
    MOTION_ENDED = "motion-ended"
    """The arm stopped after its holder's last connection had closed."""
    IDLE_TIMEOUT = "idle-timeout"
    """Nothing was done for `ServiceConfig`'s idle time."""
    TURN_STARTED = "turn-started"
    """The queue gave the arm to the student whose turn began."""
    TURN_ENDED = "turn-ended"
    """The queue took the arm back at the end of a turn."""
    SERVICE_CLOSED = "service-closed"
    """The server shut down."""

    @property
    def template(self) -> str:
        """The words with ``{by}`` (who) and ``{command}`` (its label) to fill in."""
        return _WORDS[self]

    def words(self, by: str | None = None, command: str | None = None) -> str:
        """The student's words; ``by`` names the person, ``command`` the command's label."""
        return _WORDS[self].format(by=by or "someone", command=command or "a command")


_WORDS: dict[LeaseReason, str] = {
    LeaseReason.ACQUIRED: "{by} took control",
    LeaseReason.TAKEN_BY_COMMAND: "{by} took control by using {command}",
    LeaseReason.TAKEN_OVER: "{by} took control over",
    LeaseReason.RELEASED: "{by} gave control back",
    LeaseReason.COMMAND_FAILED: "control went back because {by}'s command failed",
    LeaseReason.HOLDER_LEFT_MOVING: "{by}'s last connection closed while the arm moves",
    LeaseReason.HOLDER_RECONNECTED: "{by} is connected again",
    LeaseReason.HOLDER_DISCONNECTED: "control is free: {by}'s last connection closed",
    LeaseReason.MOTION_ENDED: "control is free: the arm stopped after its holder left",
    LeaseReason.IDLE_TIMEOUT: "control ended after a while with nothing done",
    LeaseReason.TURN_STARTED: "{by}'s turn at the robot began",
    LeaseReason.TURN_ENDED: "{by}'s turn at the robot ended",
    LeaseReason.SERVICE_CLOSED: "the server is shutting down",
}
assert set(_WORDS) == set(LeaseReason), "every lease reason has its words"


__all__ = ["LeaseReason"]
