"""The robot's own events as audit notes (`RobotNote`): control changing hands, an alarm
raised or cleared, the link down or up. Pure: the service hands them to its audit sink
(`Dispatcher.note`); `melfa.vocab.robot_log` has their words."""

from __future__ import annotations

from melfa.service.events import Actor, Alarm, RobotNote
from melfa.service.lease import LeaseChange
from melfa.vocab.link import LinkStatus
from melfa.vocab.robot_log import NoteKind

__all__ = ["NOTED_LINK", "LinkNotes", "alarm_notes", "control_note"]

NOTED_LINK = frozenset({LinkStatus.CONNECTED, LinkStatus.LOST, LinkStatus.CLOSED})
"""The link states a robot's log keeps: up, lost, closed (not every reconnect attempt)."""


def _user(actor: Actor | None) -> str | None:
    return None if actor is None else actor.user


def control_note(change: LeaseChange) -> RobotNote:
    """Who has control now and why; ``by`` is the person the reason's words name (the new
    holder, else the one who lost or gave it)."""
    by = change.holder if change.holder is not None else change.previous
    return RobotNote(
        actor=change.actor,
        kind=NoteKind.CONTROL,
        facts={
            "reason": change.reason.value,
            "by": _user(by),
            "holder": _user(change.holder),
            "previous": _user(change.previous),
            "command": None if change.command is None else change.command.label,
        },
    )


def alarm_notes(before: Alarm | None, after: Alarm | None, holder: Actor | None) -> list[RobotNote]:
    """An alarm that went (cleared) and one that came (raised), by number; ``holder`` had
    control then (the actor of the note: whose run or move it stopped)."""
    if (before and before.number) == (after and after.number):
        return []
    notes = []
    if before is not None:
        notes.append(
            RobotNote(actor=holder, kind=NoteKind.ALARM_CLEARED, facts={"number": before.number})
        )
    if after is not None:
        facts = {"number": after.number, "text": after.text, "line": after.line}
        notes.append(RobotNote(actor=holder, kind=NoteKind.ALARM, facts=facts))
    return notes


class LinkNotes:
    """The link's notes: one when it went to a state the log keeps that is not the last
    one noted (a link retrying for an hour notes "lost" once)."""

    def __init__(self) -> None:
        self.last: LinkStatus | None = None

    def changed(self, status: LinkStatus) -> RobotNote | None:
        if status not in NOTED_LINK or status is self.last:
            return None
        self.last = status
        return RobotNote(kind=NoteKind.LINK, facts={"status": status.value})
