"""The queue for a shared robot in words: what happened in it (`QueueStep`), where each
student stands (`EntryState`), what a turn's end does to a running program (`TurnEnd`),
and every other word the queue's panel, its claim dialog and the desktop's queue line
show (`QueueWords`, served as ``QUEUE_WORDS``).

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
from dataclasses import dataclass


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
    PREFLIGHT_AGAIN = "preflight-again"
    """The lab's cell was edited: the queued text's pass no longer counts, and at its turn
    the arm would refuse it (`Refusal.CELL_CHANGED`) unless it passes again."""
    PREFLIGHT_NEEDED = "preflight-needed"
    """The instructor's gate was switched on: the queued text never passed pre-flight."""
    PREFLIGHT_OK = "preflight-ok"
    """The queued text passes the instructor's gate again (it passed pre-flight again, the
    edit of the cell was undone, or the gate was switched off)."""

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
            user=user or QUEUE_WORDS.someone,
            by=by or QUEUE_WORDS.the_instructor,
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
    QueueStep.PREFLIGHT_AGAIN: (
        "the lab's cell was changed: {user}'s queued program must pass pre-flight again"
    ),
    QueueStep.PREFLIGHT_NEEDED: "{user}'s queued program must pass pre-flight before their turn",
    QueueStep.PREFLIGHT_OK: "{user}'s queued program may run on the lab robot again",
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


class RunDropped(enum.StrEnum):
    """Why a run that waited for the supervisor's *Arm ready* (attended mode) did not start;
    its `words` are the refusal the student's *Run* gets."""

    CLOSING = "closing"
    REPLACED = "replaced"
    """A newer run of theirs waits instead."""
    STOPPED = "stopped"
    TURN_ENDED = "turn-ended"

    @property
    def words(self) -> str:
        return "the run did not start: " + _DROPPED_WORDS[self]


_DROPPED_WORDS: dict[RunDropped, str] = {
    RunDropped.CLOSING: "the server is shutting down",
    RunDropped.REPLACED: "a newer run replaced it",
    RunDropped.STOPPED: "STOP was pressed while it waited for the supervisor",
    RunDropped.TURN_ENDED: "the turn ended",
}
assert set(_DROPPED_WORDS) == set(RunDropped)


@dataclass(frozen=True)
class QueueWords:
    """The queue's words beside its steps: the panel (the browser's, and the desktop
    client's one line), the claim dialog, the instructor's controls and what a failed
    request is called. Templates fill ``{user}``, ``{count}``, ``{left}`` (a clock,
    ``3:05``), ``{minutes}``, ``{seconds}``, ``{position}``, ``{countdown}``."""

    title: str = "Lab robot queue"
    someone: str = "someone"
    """``{user}`` when a step names nobody."""
    the_instructor: str = "the instructor"
    """``{by}`` when a step does not say who did it."""
    paused: str = "paused"
    attended: str = "attended"
    attended_hint: str = "Each run waits for the supervisor's Arm ready"
    waiting: str = "{count} waiting"
    empty: str = "empty: the arm is free"
    at_arm: str = "At the arm"
    you: str = "you"
    mine: str = "{user} (you)"
    left: str = "{left} left"
    held: str = "held by the instructor ({left} kept)"
    away: str = "away"
    ending: str = "time is up: finishing"
    run_waiting: str = "run waits for Arm ready"
    done: str = "Done: give the arm back"
    join: str = "Run on the lab robot"
    join_hint: str = (
        "Queue the editor's program and points for the lab robot (they must pass pre-flight)"
    )
    update: str = "Update my queued program"
    leave: str = "Leave the queue"
    next: str = "next"
    starts_in: str = "in ≈ {left}"
    now: str = "now"
    """A countdown at zero."""
    cycle: str = "runs {seconds} s"
    cycle_hint: str = "Its cycle time in pre-flight"
    stale: str = "changed since queued"
    stale_hint: str = (
        "The program in the workspace changed since it was queued: update it, or the queued "
        "one runs"
    )
    preflight_again: str = "must pass pre-flight again"
    """An entry whose pass no longer counts (the lab's cell was changed)."""
    preflight_again_hint: str = (
        "The lab's cell was changed after this program passed pre-flight: at its turn the "
        "arm would refuse it. Run pre-flight again in the cell as it is now; your queued "
        "program is then updated with the editor's"
    )
    preflight_needed: str = "must pass pre-flight"
    """An entry that never passed (the instructor's gate was switched on since)."""
    preflight_needed_hint: str = (
        "The lab robot now runs only programs that passed pre-flight: at its turn the arm "
        "would refuse this one. Run pre-flight; your queued program is then updated with "
        "the editor's"
    )
    preflight: str = "Run pre-flight"
    # The instructor's controls
    controls: str = "Instructor's queue controls"
    move_up: str = "Move {user} up"
    move_up_hint: str = "Move {user} up one place"
    skip: str = "Skip"
    skip_hint: str = "Take {user} out of the queue"
    pause: str = "Pause"
    resume: str = "Resume"
    take: str = "Take the arm"
    take_hint: str = "Take the arm now; the queue pauses and the turn keeps its time"
    extend: str = "+{minutes} min"
    end_turn: str = "End turn"
    end_turn_hint: str = "End {user}'s turn"
    attended_switch: str = "Attended"
    ready: str = "Arm ready"
    # The claim: the dialog that cannot be missed, the tab's title, a turn ending soon
    claim_title: str = "Your turn at the lab robot"
    claim_text: str = (
        "The arm is yours if you claim it within {countdown}. Claiming loads your queued "
        "program and runs it; watch the arm, STOP is always there. If you let the time run "
        "out you move back one place."
    )
    missed_once: str = "You missed it once already."
    missed_times: str = "You missed it {count} times already."
    claim: str = "Claim the arm and run"
    claim_hint: str = "Your turn at the lab robot: claim it before the time ends"
    later: str = "Not yet"
    tab_turn: str = "Your turn!"
    warned_title: str = "Your turn ends soon"
    claiming: str = "Claiming the arm"
    claimed: str = "Your turn at the lab robot: your queued program loads and runs"
    # The desktop client's one line in its status bar
    line_turn: str = "{user} ({minutes} min left)"
    line_offered: str = "the arm is offered to you: claim it now"
    line_place: str = "you are number {position}, in about {minutes} min"
    line_preflight: str = "your queued program must pass pre-flight again (Pre-flight, in the IDE)"
    """When the arm would refuse its user's queued program (the lab's cell was changed)."""
    # What a refused or failed request is called (the server's reason follows)
    join_failed: str = "Could not join the queue"
    leave_failed: str = "Could not leave the queue"
    claim_failed: str = "Could not claim the arm"
    done_failed: str = "Could not give the arm back"
    move_failed: str = "Could not reorder the queue"
    skip_failed: str = "Could not skip"
    pause_failed: str = "Could not change the queue"
    take_failed: str = "Could not take the arm"
    extend_failed: str = "Could not extend"
    attended_failed: str = "Could not switch attended mode"
    ready_failed: str = "Could not say arm ready"


QUEUE_WORDS = QueueWords()


__all__ = ["QUEUE_WORDS", "EntryState", "QueueStep", "QueueWords", "RunDropped", "TurnEnd"]
