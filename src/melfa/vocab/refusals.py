"""Why the robot service refused a command: one member per reason, with the student's words
and the fix.

The wire value is the code every door sends (REST's ``error.code``, the WebSocket's
``error`` message; rosbridge and the thesis's messages send the words): `Refusal.says` is
what happened, `Refusal.fix` what to do about it, both templates filled with the facts of
the refusal (who holds the robot, which line), and `Refusal.offer` the one-click fix a
client may show (``preflight``: run pre-flight), when there is one. The service raises
`melfa.service.policy.Refused` with a member; nothing downstream parses the words.

>>> Refusal.SIMULATION_REQUIRED.value, Refusal.SIMULATION_REQUIRED.offer
('simulation-required', 'preflight')
>>> Refusal.LEASE_REQUIRED.words(holder="ann")
('ann holds the robot.', 'Ask them to release it, or an instructor to take over.')

The gate's fix depends on what was refused (`Asked`): a refused run of the program the
robot holds needs a pre-flight and the run again, not a new load.

>>> Refusal.CELL_CHANGED.words(asked=Asked.RUN)[1].endswith("run it again: it is still loaded.")
True
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field


class Refusal(enum.StrEnum):
    """Why a command was not queued (stable wire value)."""

    LEASE_REQUIRED = "lease-required"
    """Someone else holds the lab robot (the operator lease)."""
    LEASE_NOT_TAKEN = "lease-not-taken"
    """Nobody holds the robot and this service does not hand the lease out by itself."""
    OBSERVER = "observer"
    """An observer's account never moves the robot."""
    PROGRAM_HAS_ERRORS = "program-has-errors"
    """Check-before-upload: the checker found an error, or the program cannot be sent as it
    is (a non-ASCII character in code, numbering that would change its meaning)."""
    POINTS_HAVE_ERRORS = "points-have-errors"
    SIMULATION_REQUIRED = "simulation-required"
    """The instructor's gate: the lab robot loads and runs only a program and points that
    passed pre-flight (a simulated run without errors)."""
    CELL_CHANGED = "cell-changed"
    """The instructor's gate: the program and points passed pre-flight, but in an earlier
    version of the lab's cell (an instructor moved or added a fixture, a part, the table
    since); a pass counts only in the cell as it is now."""
    SLOT_CHANGED = "slot-changed"
    """A run named the program it meant (its fingerprint), and the controller's slot holds
    another: someone loaded in between."""
    SLOT_UNKNOWN = "slot-unknown"
    """A run named the program it meant, and what the slot holds is not known (a load
    failed on the way, or it was deleted)."""
    QUEUE_ACTIVE = "queue-active"
    """The lab robot has a queue: the arm goes only to whoever's turn it is."""
    TURN_OVER = "turn-over"
    """The holder's turn at the lab robot is over: the program may finish, nothing new starts."""
    NOT_YOUR_TURN = "not-your-turn"
    """A claim from someone the arm is not offered to."""
    NOT_QUEUED = "not-queued"
    """A queue operation for someone who is not in the queue."""
    HELD = "held"
    """A member of staff stopped the lab robot and holds it: nothing a student sends starts
    until they release it (`melfa.service.policy.Policy.hold`)."""
    OUTSIDE_LAB = "outside-lab"
    """The lab robot is driven only from the lab's networks (`melfa serve --lab-network`,
    the instructor's desk), and this came from elsewhere (`melfa.service.lab_network`)."""

    def words(self, asked: Asked | None = None, **facts: object) -> tuple[str, str]:
        """(what happened, the fix), with ``facts`` filled in; the fix for what was
        ``asked`` where it has its own (a refused run is not mended as a refused load)."""
        words = _WORDS[self]
        fix = words.fixes.get(asked, words.fix) if asked is not None else words.fix
        return words.says.format(**facts), fix.format(**facts)

    @property
    def offer(self) -> str | None:
        """The one-click fix a client may offer (None: none)."""
        return _WORDS[self].offer

    @property
    def offer_label(self) -> str | None:
        return _WORDS[self].offer_label


class Asked(enum.StrEnum):
    """What a refused command asked for, where the fix depends on it (the gate's)."""

    LOAD = "load"
    """Load a program or points (the policy's load commands): the text must pass first."""
    RUN = "run"
    """Run what the robot holds: it stays loaded, so no new load is needed."""
    QUEUE = "queue"
    """Join the lab robot's queue with a text (`Policy.may_queue`)."""

    @property
    def after_fix(self) -> str:
        """What to do once the one-click fix (pre-flight) passed."""
        return _AFTER_FIX[self]


_AFTER_FIX: dict[Asked, str] = {
    Asked.LOAD: "Load the project again: the lab robot takes this program now.",
    Asked.RUN: "Press Run again: the program the robot holds may run now, no new load needed.",
    Asked.QUEUE: "Join the queue again: the lab robot takes this program now.",
}


@dataclass(frozen=True)
class _Words:
    says: str
    fix: str
    """The fix (of a load, where the gate's differ)."""
    offer: str | None = None
    offer_label: str | None = None
    fixes: dict[Asked, str] = field(default_factory=dict)
    """The fix for what was asked, where it is not `fix`."""


_WORDS: dict[Refusal, _Words] = {
    Refusal.LEASE_REQUIRED: _Words(
        "{holder} holds the robot.", "Ask them to release it, or an instructor to take over."
    ),
    Refusal.LEASE_NOT_TAKEN: _Words(
        "Nobody holds the robot.", "Take control of the robot first, then try again."
    ),
    Refusal.OBSERVER: _Words(
        "{user} is an observer and cannot move the robot.",
        "Sign in as a student or an instructor to drive it.",
    ),
    Refusal.PROGRAM_HAS_ERRORS: _Words(
        "Line {line}: {message}", "Fix it in the editor, then load again."
    ),
    Refusal.POINTS_HAVE_ERRORS: _Words(
        "Points line {line}: {message}", "Fix the point, then load again."
    ),
    Refusal.SIMULATION_REQUIRED: _Words(
        "This lab runs a program on the robot only after the same program and points "
        "passed pre-flight (a simulated run without errors).",
        "Run Pre-flight (or debug it on My simulator), then load and run it again.",
        "preflight",
        "Run pre-flight",
        {
            Asked.QUEUE: "Run Pre-flight (or debug it on My simulator), then join the queue "
            "with it again."
        },
    ),
    Refusal.CELL_CHANGED: _Words(
        "The lab's cell (its table, fixtures or parts) was changed after this program and "
        "points passed pre-flight, so that pre-flight no longer counts.",
        "Run Pre-flight again in the cell as it is now, then load it and run it.",
        "preflight",
        "Run pre-flight",
        {
            Asked.RUN: "Run Pre-flight again on the program the robot holds, in the cell as "
            "it is now, then run it again: it is still loaded.",
            Asked.QUEUE: "Run Pre-flight again in the cell as it is now, then join the queue "
            "with it again.",
        },
    ),
    Refusal.SLOT_CHANGED: _Words(
        "The robot now holds {who}'s program, not the one you meant to run.",
        "Look at what is loaded, or load yours, then press Run again.",
        "load-project",
        "Load project",
    ),
    Refusal.SLOT_UNKNOWN: _Words(
        "Nobody knows which program the robot holds now: the last load did not finish.",
        "Load the project, then press Run again.",
        "load-project",
        "Load project",
    ),
    Refusal.QUEUE_ACTIVE: _Words(
        "The lab robot has a queue: the arm goes to whoever's turn it is.",
        "Join the queue with Run on the lab robot; the arm is offered to you when your turn comes.",
    ),
    Refusal.TURN_OVER: _Words(
        "Your turn at the lab robot is over.",
        "Let the program finish (or stop it); join the queue again for another run.",
    ),
    Refusal.NOT_YOUR_TURN: _Words(
        "The arm is not offered to you yet.",
        "Wait for your turn: the queue panel shows your place and when it comes.",
    ),
    Refusal.NOT_QUEUED: _Words(
        "{user} is not in the queue.", "Join the queue with Run on the lab robot."
    ),
    Refusal.HELD: _Words(
        "{who} stopped the robot and is holding it.",
        "Wait until they release it; ask them if you are not sure why.",
    ),
    Refusal.OUTSIDE_LAB: _Words(
        "The lab robot can be driven only from the lab's computers.",
        "From here, use My simulator (Pre-flight and the debugger work there too); "
        "come to the lab to run it on the arm.",
    ),
}
assert set(_WORDS) == set(Refusal), "every refusal has its words"
assert set(_AFTER_FIX) == set(Asked)


__all__ = ["Asked", "Refusal"]
