"""Control of the robot (the operator lease) in words: why it changed hands (one code per
cause), how its holder is connected (`HolderState`), and every other word the header's
control, its buttons and its toasts show (`ControlWords`, served as ``CONTROL_WORDS``).

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
from dataclasses import dataclass


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
        return _WORDS[self].format(
            by=by or CONTROL_WORDS.someone, command=command or CONTROL_WORDS.a_command
        )


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


class HolderState(enum.StrEnum):
    """How the lease holder is connected (the state's ``lease_state``, the ``lease``
    message's ``holder_state``; shown next to their name in its `words`)."""

    CONNECTED = "connected"
    """At least one open connection (IDE tab, desktop, rosbridge)."""
    NO_CONNECTION = "no connection"
    """Took the lease over REST and has no socket open (a script); idle expiry applies."""
    DISCONNECTED_MOVING = "disconnected, robot moving"
    """The last connection closed while the arm moved on their behalf."""

    @property
    def words(self) -> str:
        return _HOLDER_WORDS[self]


_HOLDER_WORDS: dict[HolderState, str] = {
    HolderState.CONNECTED: "connected",
    HolderState.NO_CONNECTION: "no connection",
    HolderState.DISCONNECTED_MOVING: "disconnected, robot moving",
}
assert set(_HOLDER_WORDS) == set(HolderState), "every holder state has its words"


@dataclass(frozen=True)
class ControlWords:
    """Who holds control, the buttons that take and give it, the toasts when it changes
    hands under a student (the header of the browser; the desktop's control row) and what
    the first-run guide says to do while someone else holds it.
    Templates fill ``{user}``, ``{by}``, ``{time}``, ``{state}``, ``{command}``,
    ``{release}`` (the button's own word)."""

    group: str = "Who controls the robot"
    """The header's group, for a screen reader (the tab *Robot control* is the jog's)."""
    someone: str = "someone"
    """``{by}`` when a change names nobody."""
    a_command: str = "a command"
    """``{command}`` when a change does not say which."""
    control: str = "Control:"
    you: str = "you"
    free: str = "free"
    since: str = "since {time}"
    you_hold: str = "You hold control"
    holds: str = "{user} holds control"
    nobody: str = "Nobody holds control"
    first_takes: str = "the first to move the robot takes it"
    """Said after `nobody` (the browser's tooltip) or `free` (the desktop's row)."""
    by_queue: str = "by the queue"
    """Nobody holds control and someone waits in the queue: only the queue gives it."""
    queue_gives: str = "while anyone waits, the queue gives it in turn"
    take: str = "Take control"
    release: str = "Release"
    take_over: str = "Take over"
    taken_over_title: str = "Control taken over"
    taken_over: str = "{by} took control of the robot."
    an_instructor: str = "An instructor"
    yours_title: str = "You have control of the robot"
    yours: str = (
        "Taken when you used {command}. Others can watch; press {release} when you are done."
    )
    take_failed: str = "Could not take control"
    release_failed: str = "Could not release control"
    take_over_failed: str = "Could not take over"
    held_load: str = (
        "Wait until they release it, or switch to My simulator (top) to try on your own "
        "simulated arm, then press Load project again."
    )
    """The first-run guide's what to do when Load was refused: someone else holds control."""


CONTROL_WORDS = ControlWords()


__all__ = ["CONTROL_WORDS", "ControlWords", "HolderState", "LeaseReason"]
