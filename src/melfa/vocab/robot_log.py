"""What happened to a robot that no command asked for, as the audit log keeps it beside
the robot's commands: control changing hands, an alarm raised or cleared, the link going
down or up. With the commands (``robot.<command>``) these make a robot's log: the desk
reads one robot's entries (``details.robot``: ``lab``, or ``sim:<user>`` for a user's
private simulator) in local time and plain words.

The service writes a `RobotNote` (`melfa.service.events`) with a `NoteKind` and its facts;
the store keeps the kind's value as the entry's action; the browser fills `NOTE_WORDS`
(served as ``/vocab.js``) with those facts, never a sentence the server wrote.
"""

from __future__ import annotations

import enum

__all__ = ["LAB_ROBOT", "NOTE_WORDS", "ROBOT_LOG_WORDS", "NoteKind", "simulator_of"]

LAB_ROBOT = "lab"
"""The lab robot's name in the audit's ``details.robot``."""


def simulator_of(user: str) -> str:
    """A user's private simulator's name in the audit's ``details.robot``."""
    return f"sim:{user}"


class NoteKind(enum.StrEnum):
    """What happened (the audit entry's action)."""

    CONTROL = "control.changed"
    """Control (the operator lease) changed hands; ``reason`` (`LeaseReason`), ``by``,
    ``holder``, ``command`` (its label)."""
    ALARM = "alarm.raised"
    """The controller raised an alarm; ``number``, ``text``, ``line`` (a run-time error's
    line in the loaded text, or null)."""
    ALARM_CLEARED = "alarm.cleared"
    """The alarm ``number`` is gone (reset, or cleared at the controller)."""
    LINK = "link.changed"
    """The line to the controller went up or down; ``status`` (`LinkStatus`)."""


NOTE_WORDS: dict[str, str] = {
    NoteKind.ALARM.value: "Alarm {number}: {text}",
    "alarm-line": "Alarm {number} at line {line}: {text}",
    NoteKind.ALARM_CLEARED.value: "Alarm {number} cleared",
    NoteKind.LINK.value: "{words}",
    NoteKind.CONTROL.value: "{words}",
}
"""The audit view's words of a note; control changes use `LeaseReason`'s words and link
changes `LINK_WORDS`, both already served."""

ROBOT_LOG_WORDS: dict[str, str] = {
    "title": "Robot log",
    "robot": "Robot",
    "lab": "Lab robot",
    "simulator": "{who}'s simulator",
    "help": (
        "What happened to this robot: who took control, what they ran or moved, every STOP, "
        "alarms and the link, newest first (the last {limit} entries, in your local time)."
    ),
    "empty": "Nothing has happened to this robot yet.",
    "columns": "When,Who,What,Result",
    "csv": "Export CSV",
    "file": "robot-log-{robot}.csv",
    "mine-title": "Your robot log",
    "mine-help": (
        "What you asked the robot you drive to do and what it answered, kept by the server"
    ),
    "mine-columns": "Time,Action,Result",
    "mine-empty": "Nothing yet: load, run or move the robot and it is listed here.",
}
"""The desk's robot log pane (``{who}``: the simulator's user, ``{limit}``: how many; its
CSV's ``file`` name: ``{robot}``, ``lab`` or ``sim-<user>``), and
the IDE's *Robot log* of one's own entries (``mine-…``)."""
