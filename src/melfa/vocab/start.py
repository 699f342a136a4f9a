"""How a run on a student's own simulator starts, and the words the IDE shows for it.

Pure: the debugger's start options (`melfa.web.debug_models.StartIn`) carry these codes;
the IDE's "How the run starts" box shows `START_WORDS` and the words of each choice
(`/vocab.js`). `melfa.sim.interp.start.RunStart` is what they become.
"""

from __future__ import annotations

import enum


class StartServo(enum.StrEnum):
    """The servo when the run starts."""

    AS_IT_IS = "as-it-is"
    """As the simulator's servo is now."""
    ON = "on"
    OFF = "off"


class StartPlace(enum.StrEnum):
    """Where the arm stands when the run starts."""

    AS_IT_STANDS = "as-it-stands"
    """Where the simulator's arm stands now."""
    JOINTS = "joints"
    """At six joint angles (degrees)."""
    POSE = "pose"
    """At a position in XYZ (mm, degrees, flags), solved to joints."""


SERVO_WORDS: dict[StartServo, str] = {
    StartServo.AS_IT_IS: "As the simulator is",
    StartServo.ON: "On",
    StartServo.OFF: "Off",
}

PLACE_WORDS: dict[StartPlace, str] = {
    StartPlace.AS_IT_STANDS: "Where the simulator's arm stands",
    StartPlace.JOINTS: "At joint angles (°)",
    StartPlace.POSE: "At a position (X, Y, Z mm; A, B, C °)",
}

START_WORDS: dict[str, str] = {
    "title": "How the run starts",
    "servo": "Servo",
    "place": "The arm starts",
    "flags": "Flags (FL1, FL2)",
    "override": "Override (%)",
    "override_hint": "Empty: as the simulator is",
    "feed": "Lines for INPUT #",
    "feed_file": "File #",
    "feed_line": "Line the program reads",
    "feed_add": "Add a line",
    "feed_remove": "Remove this line",
}

__all__ = ["PLACE_WORDS", "SERVO_WORDS", "START_WORDS", "StartPlace", "StartServo"]
