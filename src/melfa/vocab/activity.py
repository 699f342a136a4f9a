"""What the robot is doing, as one word every view shows the same way (the header, the
activity line, the jog pad, the 3D view, the desktop client, ROS), and the student's
sentence for it, written once.

Pure: `activity_of` computes the word from the polled state and the service's note of the
motion it last started (`Motion`, with its `MotionPhase`), so a *Move to* is never reported
as "running line 50" (not even with a program paused), "At P1" is said only once the arm
has arrived, and a held jog key never as "not moving". `ACTIVITY_WORDS` holds the sentence of each
word; `said` fills it (the browser gets the same table in the generated ``/vocab.js`` and
fills it the same way).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class Activity(enum.StrEnum):
    OFFLINE = "offline"
    """The robot link is down."""
    UPLOADING = "uploading"
    ALARM = "alarm"
    JOGGING = "jogging"
    MOVING_TO = "moving-to"
    """A *Move to* (or a step jog, an executed statement) is moving the arm."""
    RUNNING = "running"
    PAUSED = "paused"
    """The program was stopped mid-way: *Run* continues, *Reset program* starts over."""
    AT = "at"
    """A *Move to* arrived: the arm stands at its point (until the next motion)."""
    MOVING = "moving"
    """The arm moves and melfa did not start it (the pendant, another program)."""
    IDLE = "idle"


class Tone(enum.StrEnum):
    """How a view marks the activity: a spinner (busy), red (error), plain (calm)."""

    CALM = "calm"
    BUSY = "busy"
    ERROR = "error"


@dataclass(frozen=True)
class ActivityWords:
    """The sentence of an activity: ``said`` with its detail (``{detail}``: the target, the
    line, the jog key, the alarm's code), ``bare`` without one, the header's ``pill``."""

    said: str
    bare: str
    pill: str
    tone: Tone
    hint: str = ""


ACTIVITY_WORDS: dict[Activity, ActivityWords] = {
    Activity.OFFLINE: ActivityWords(
        "Robot not connected", "Robot not connected", "offline", Tone.ERROR
    ),
    Activity.UPLOADING: ActivityWords(
        "Sending a program to the robot…", "Sending a program to the robot…", "uploading",
        Tone.BUSY,
    ),
    Activity.ALARM: ActivityWords("Alarm {detail}", "Alarm", "alarm", Tone.ERROR),
    Activity.JOGGING: ActivityWords("Jogging {detail}", "Jogging", "jogging", Tone.BUSY),
    Activity.MOVING_TO: ActivityWords(
        "Moving to {detail}", "Moving to a point", "moving", Tone.BUSY
    ),
    Activity.RUNNING: ActivityWords("Running {detail}", "Running", "running", Tone.BUSY),
    Activity.PAUSED: ActivityWords(
        "Paused at {detail}", "Paused", "paused", Tone.CALM,
        "Run continues; Reset program starts over",
    ),
    Activity.AT: ActivityWords("At {detail}", "At the point", "idle", Tone.CALM),
    Activity.MOVING: ActivityWords(
        "Robot moving (not started by melfa)", "Robot moving (not started by melfa)", "moving",
        Tone.BUSY,
    ),
    Activity.IDLE: ActivityWords("Idle", "Idle", "idle", Tone.CALM),
}  # fmt: skip

FRAME_WORDS = {"xyz": "{axis} (base)", "tool": "{axis} (tool)", "joint": "{axis}"}
"""A jog key in its frame: the service's jog detail is ``<frame> <axis><sign>``."""

WHERE_WORDS = {
    "line": "line {line}",
    "line_of": "line {line} of {file}",
    "step": "line numbered {step}",
}
"""Where a program is: the student's line (in the editor, or of a named file), else the
controller's step number when this client does not know the loaded text."""


def said(activity: Activity, detail: str = "") -> str:
    """The activity's sentence with its detail.

    >>> said(Activity.MOVING_TO, "P1"), said(Activity.MOVING_TO)
    ('Moving to P1', 'Moving to a point')
    """
    words = ACTIVITY_WORDS[activity]
    return words.said.replace("{detail}", detail) if detail else words.bare


def jog_detail(detail: str) -> str:
    """The service's jog detail (``xyz X+``, a frame code and the key) as a student reads it.

    >>> jog_detail("xyz X+"), jog_detail("tool Z-"), jog_detail("joint J3+"), jog_detail("")
    ('X+ (base)', 'Z- (tool)', 'J3+', '')
    """
    frame, _, axis = detail.partition(" ")
    if not axis:
        return detail
    return FRAME_WORDS.get(frame, "{axis}").replace("{axis}", axis)


def where(*, line: int | None = None, file: str = "", step: int | None = None) -> str:
    """Where the program is, in the student's words.

    >>> where(line=5), where(line=5, file="pick.MB4"), where(step=50), where()
    ('line 5', 'line 5 of pick.MB4', 'line numbered 50', '')
    """
    if line is not None:
        template = WHERE_WORDS["line_of"] if file else WHERE_WORDS["line"]
        return template.replace("{line}", str(line)).replace("{file}", file)
    if step:
        return WHERE_WORDS["step"].replace("{step}", str(step))
    return ""


class MotionKind(enum.Enum):
    RUN = "run"
    MOVE_TO = "move_to"
    STEP = "step"
    EXEC = "exec"


class MotionPhase(enum.Enum):
    """Where a motion melfa started is (the service moves it on from its STATE reads)."""

    ASKED = "asked"
    """Queued or on the wire: the controller has not answered yet."""
    SENT = "sent"
    """The controller took it; no STATE read since has shown the arm move."""
    MOVING = "moving"
    """A STATE read showed it moving."""
    ARRIVED = "arrived"
    """A STATE read after it was sent showed the arm still: it is over."""


@dataclass(frozen=True)
class Motion:
    """The motion the service last started, what to call it (``P1``, ``X+``), and where it
    is (`MotionPhase`)."""

    kind: MotionKind
    label: str = ""
    phase: MotionPhase = MotionPhase.ASKED

    def after_state_read(self, moving: bool) -> Motion:
        """The motion after a STATE read that showed the arm ``moving`` (or still).

        >>> m = Motion(MotionKind.MOVE_TO, "P1", MotionPhase.SENT)
        >>> m.after_state_read(True).phase, m.after_state_read(False).phase
        (<MotionPhase.MOVING: 'moving'>, <MotionPhase.ARRIVED: 'arrived'>)
        >>> Motion(MotionKind.MOVE_TO, "P1").after_state_read(False).phase  # not answered yet
        <MotionPhase.ASKED: 'asked'>
        """
        if self.phase is MotionPhase.ASKED or self.phase is MotionPhase.ARRIVED:
            return self
        phase = MotionPhase.MOVING if moving else MotionPhase.ARRIVED
        return self if phase is self.phase else Motion(self.kind, self.label, phase)


@dataclass(frozen=True)
class Facts:
    """The polled facts `activity_of` needs (from the service's `StateSnapshot`)."""

    connected: bool
    busy: str | None = None
    alarm: bool = False
    jogging: bool = False
    running: bool | None = None
    program_running: bool | None = None
    paused: bool | None = None
    moving: bool | None = None
    line: int | None = None


def activity_of(facts: Facts, motion: Motion | None) -> tuple[Activity, str]:
    """The activity and its detail (the target, the line). A motion melfa started and
    that has not arrived is "moving to" whatever the program's flags say (a *Move to*
    with a program paused); one that arrived is "at" its point until the next.

    >>> activity_of(Facts(True, running=True, program_running=False),
    ...             Motion(MotionKind.MOVE_TO, "P1"))
    (<Activity.MOVING_TO: 'moving-to'>, 'P1')
    >>> activity_of(Facts(True, running=True, program_running=True, line=30), None)
    (<Activity.RUNNING: 'running'>, 'line 30')
    >>> activity_of(Facts(True, running=False, paused=True, line=35),
    ...             Motion(MotionKind.MOVE_TO, "Ppila", MotionPhase.ARRIVED))
    (<Activity.AT: 'at'>, 'Ppila')
    """
    if not facts.connected:
        return Activity.OFFLINE, ""
    if facts.busy:
        return Activity.UPLOADING, ""
    if facts.alarm:
        return Activity.ALARM, ""
    if facts.jogging:
        return Activity.JOGGING, motion.label if motion and motion.kind is MotionKind.STEP else ""
    moving = bool(facts.running) or bool(facts.moving)
    ours = motion is not None and motion.kind is not MotionKind.RUN
    if ours and motion is not None and motion.phase is not MotionPhase.ARRIVED:
        return Activity.MOVING_TO, motion.label
    if facts.program_running or (facts.running and motion and motion.kind is MotionKind.RUN):
        return Activity.RUNNING, f"line {facts.line}" if facts.line else ""
    if moving and ours and motion is not None:  # arrived, and moving again: not ours
        return Activity.MOVING, ""
    if ours and motion is not None and motion.kind is MotionKind.MOVE_TO:
        return Activity.AT, motion.label
    if facts.paused:
        return Activity.PAUSED, f"line {facts.line}" if facts.line else ""
    if moving:
        return Activity.MOVING, ""
    return Activity.IDLE, ""


__all__ = [
    "ACTIVITY_WORDS",
    "FRAME_WORDS",
    "WHERE_WORDS",
    "Activity",
    "ActivityWords",
    "Facts",
    "Motion",
    "MotionKind",
    "MotionPhase",
    "Tone",
    "activity_of",
    "jog_detail",
    "said",
    "where",
]
