"""What a student can ask of the robot: one member per command of the robot service.

The wire value is the name the service puts in audit entries and ``result`` events (and
the audit log keeps); `Command.label` is the student's words for it (a log line, a toast:
never the Python method name); `Command.moves` says whether it moves the arm (a moving
command keeps the lease of a holder who left until the arm is still, and audit entries
carry it).

>>> Command.MOVE_TO.value, Command.MOVE_TO.label, Command.MOVE_TO.moves
('move_to', 'Move to', True)
>>> Command.SERVO.label, Command.SERVO.moves
('Servo', False)
>>> command_label("load_project"), command_label("brand_new_command")
('Load project', 'Brand new command')
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class Command(enum.StrEnum):
    """A command of the robot service (stable wire value: what ``result`` events carry)."""

    LOAD_PROJECT = "load_project"
    UPLOAD_PROGRAM = "upload_program"
    UPLOAD_POINTS = "upload_points"
    DELETE = "delete"
    RUN = "run"
    STOP = "stop"
    MOVE_TO = "move_to"
    EXEC = "exec"
    """One MELFA BASIC statement now (``EXEC``); it may move the arm."""
    SERVO = "servo"
    OVERRIDE = "override"
    HAND = "hand"
    JOG = "jog"
    """Hold-to-move: the first JOG and each renewal."""
    JOG_STOP = "jog_stop"
    """The key was let go: JOG with empty masks."""
    JOG_END = "jog_end"
    """The audit entry of a jog that ended (released, stopped, heartbeat lost …)."""
    JOG_STEP = "jog_step"
    RESET_ALARM = "reset_alarm"
    RESET_PROGRAM = "reset_program"
    READ_JOINTS = "read_joints"
    READ_POSE = "read_pose"
    TAKE_CONTROL = "take_control"
    """Take the free operator lease (the audit keeps a refused one; an accepted one is the
    control change it makes)."""
    JOIN_QUEUE = "join_queue"
    """Enter the shared robot's queue (the audit keeps a refused one; an accepted one is
    the queue's step). So too the three below."""
    CLAIM_TURN = "claim_turn"
    """Claim the arm the queue offers."""
    LEAVE_QUEUE = "leave_queue"
    """Leave the queue before one's turn."""
    GIVE_BACK = "give_back"
    """Give the arm back before the turn's end."""

    @property
    def label(self) -> str:
        """The student's words (``Move to``)."""
        return _WORDS[self].label

    @property
    def moves(self) -> bool:
        """Whether the command moves the arm."""
        return _WORDS[self].moves

    @property
    def detail_in_words(self) -> bool:
        """Whether its audit detail reads as words a person may be shown (``on``, ``30%``,
        the student's own statement); else it is what melfa built for the controller (a
        move's statements, a slot) and logs show the label alone."""
        return self in _DETAIL_IN_WORDS

    @property
    def queue(self) -> bool:
        """Whether it is a request of the shared robot's queue (the desk's audit shows a
        refused one among the queue's steps)."""
        return self in _QUEUE

    @property
    def control(self) -> bool:
        """Whether it asks for control of the robot (the desk's audit shows a refused one
        among the control changes)."""
        return self is Command.TAKE_CONTROL


@dataclass(frozen=True)
class _Words:
    label: str
    moves: bool


_WORDS: dict[Command, _Words] = {
    Command.LOAD_PROJECT: _Words("Load project", False),
    Command.UPLOAD_PROGRAM: _Words("Upload program", False),
    Command.UPLOAD_POINTS: _Words("Upload points", False),
    Command.DELETE: _Words("Delete program", False),
    Command.RUN: _Words("Run", True),
    Command.STOP: _Words("Stop", False),
    Command.MOVE_TO: _Words("Move to", True),
    Command.EXEC: _Words("Instruction", True),
    Command.SERVO: _Words("Servo", False),
    Command.OVERRIDE: _Words("Speed override", False),
    Command.HAND: _Words("Hand", False),
    Command.JOG: _Words("Jog", True),
    Command.JOG_STOP: _Words("Jog stop", False),
    Command.JOG_END: _Words("Jog end", False),
    Command.JOG_STEP: _Words("Jog step", True),
    Command.RESET_ALARM: _Words("Reset alarm", False),
    Command.RESET_PROGRAM: _Words("Reset program", False),
    Command.READ_JOINTS: _Words("Read joints", False),
    Command.READ_POSE: _Words("Read position", False),
    Command.TAKE_CONTROL: _Words("Take control", False),
    Command.JOIN_QUEUE: _Words("Join the queue", False),
    Command.CLAIM_TURN: _Words("Claim the arm", False),
    Command.LEAVE_QUEUE: _Words("Leave the queue", False),
    Command.GIVE_BACK: _Words("Give the arm back", False),
}
assert set(_WORDS) == set(Command), "every command has its words"

_DETAIL_IN_WORDS = frozenset(
    {Command.EXEC, Command.SERVO, Command.OVERRIDE, Command.HAND, Command.JOG, Command.JOG_END}
)
_QUEUE = frozenset({Command.JOIN_QUEUE, Command.CLAIM_TURN, Command.LEAVE_QUEUE, Command.GIVE_BACK})


def command_label(value: str) -> str:
    """The label of a command's wire value; an unknown one (a newer server) in words made
    from its name, never the bare identifier."""
    try:
        return Command(value).label
    except ValueError:
        return value.replace("_", " ").capitalize()


__all__ = ["Command", "command_label"]
