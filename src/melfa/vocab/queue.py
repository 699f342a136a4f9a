"""The queue for a shared robot in words: what happened in it (`QueueStep`), where each
student stands (`EntryState`), and what a turn's end does to a running program
(`TurnEnd`).

The service sends codes (the ``queue`` live message, the audit's ``queue.<step>``
actions); clients show the words of the code (the browser from ``/vocab.js``'s
``QUEUE_STEPS``, the desktop client from here), filled with who (``{user}``), who did it
(``{by}``), a place in the queue (``{position}``) and seconds (``{seconds}``).

>>> QueueStep.MISSED.words(user="ann")
'ann missed the claim and moved back one place'
>>> QueueStep.ARM_READY.words(by="ivy")
'ivy said the arm is ready: the run goes'
"""

from __future__ import annotations

import enum


class QueueStep(enum.StrEnum):
    """One transition of the queue (stable wire value; audited as ``queue.<value>``)."""

    JOINED = "joined"
    UPDATED = "updated"
    """The queued text was replaced (it passed again)."""
    LEFT = "left"
    OFFERED = "offered"
    """The head of the queue is offered the arm for the claim window."""
    CLAIMED = "claimed"
    """The offer was taken: the turn begins and the lease is theirs."""
    MISSED = "missed"
    """The claim window ran out: the student moves back one place, not out."""
    WARNED = "warned"
    """The turn ends soon (told in advance)."""
    ENDING = "ending"
    """Time is up; the running program may finish, nothing new starts."""
    ENDED = "ended"
    """The turn ended on time and the arm goes to the next."""
    STOPPED = "stopped"
    """The turn ended with the program running: it was stopped."""
    FINISHED = "finished"
    """The student ended their turn early (released the arm)."""
    GONE = "gone"
    """Away longer than the grace time: out of the queue (or their turn ended)."""
    AWAY = "away"
    """The student's last connection closed: their place is kept for the grace time."""
    BACK = "back"
    STALE = "stale"
    """The workspace's text no longer matches what was queued."""
    FRESH = "fresh"
    """The workspace matches the queued text again."""
    MOVED = "moved"
    """An instructor put a student at another place."""
    SKIPPED = "skipped"
    """An instructor took a student out of the queue (or ended their turn)."""
    PAUSED = "paused"
    RESUMED = "resumed"
    EXTENDED = "extended"
    TAKEN = "taken"
    """An instructor took the arm at once; the queue is paused, the turn kept."""
    ATTENDED_ON = "attended-on"
    ATTENDED_OFF = "attended-off"
    RUN_WAITING = "run-waiting"
    """Attended mode: a run waits for the supervisor's *Arm ready*."""
    ARM_READY = "arm-ready"
    RESTORED = "restored"
    """The server started again with the queue it had."""

    @property
    def template(self) -> str:
        return _STEP_WORDS[self]

    def words(
        self,
        user: str | None = None,
        by: str | None = None,
        position: int | None = None,
        seconds: float | None = None,
    ) -> str:
        return _STEP_WORDS[self].format(
            user=user or "someone",
            by=by or "the instructor",
            position=position if position is not None else "?",
            seconds=round(seconds) if seconds is not None else "?",
        )


_STEP_WORDS: dict[QueueStep, str] = {
    QueueStep.JOINED: "{user} joined the queue",
    QueueStep.UPDATED: "{user} updated their queued program",
    QueueStep.LEFT: "{user} left the queue",
    QueueStep.OFFERED: "the arm is offered to {user}",
    QueueStep.CLAIMED: "{user} claimed the arm: their turn begins",
    QueueStep.MISSED: "{user} missed the claim and moved back one place",
    QueueStep.WARNED: "{user}'s turn ends in {seconds} s",
    QueueStep.ENDING: "{user}'s time is up: the program may finish, nothing new starts",
    QueueStep.ENDED: "{user}'s turn ended",
    QueueStep.STOPPED: "{user}'s turn ended: their program was stopped",
    QueueStep.FINISHED: "{user} gave the arm back",
    QueueStep.GONE: "{user} was away too long and left the queue",
    QueueStep.AWAY: "{user} is away: their place is kept for a while",
    QueueStep.BACK: "{user} is back",
    QueueStep.STALE: "{user}'s program changed since it was queued",
    QueueStep.FRESH: "{user}'s program matches the queued one again",
    QueueStep.MOVED: "{by} moved {user} to place {position}",
    QueueStep.SKIPPED: "{by} skipped {user}",
    QueueStep.PAUSED: "{by} paused the queue",
    QueueStep.RESUMED: "{by} resumed the queue",
    QueueStep.EXTENDED: "{by} gave {user} {seconds} s more",
    QueueStep.TAKEN: "{by} took the arm; the queue is paused",
    QueueStep.ATTENDED_ON: "{by} turned attended mode on: each run waits for Arm ready",
    QueueStep.ATTENDED_OFF: "{by} turned attended mode off",
    QueueStep.RUN_WAITING: "{user}'s run waits for the supervisor's Arm ready",
    QueueStep.ARM_READY: "{by} said the arm is ready: the run goes",
    QueueStep.RESTORED: "the queue is back after a server restart",
}
assert set(_STEP_WORDS) == set(QueueStep), "every queue step has its words"


class EntryState(enum.StrEnum):
    """Where a student stands in the queue."""

    WAITING = "waiting"
    OFFERED = "offered"
    """First in line, with the claim window open."""

    @property
    def words(self) -> str:
        return _STATE_WORDS[self]


_STATE_WORDS: dict[EntryState, str] = {
    EntryState.WAITING: "waiting",
    EntryState.OFFERED: "the arm is offered: claim it",
}
assert set(_STATE_WORDS) == set(EntryState)


class TurnEnd(enum.StrEnum):
    """What the end of a turn does to a program still running (a lab setting)."""

    STOP = "stop"
    """Stop it: the next student's time starts on time."""
    FINISH = "finish"
    """Let it finish (up to a cap); nothing new may start."""


__all__ = ["EntryState", "QueueStep", "TurnEnd"]
