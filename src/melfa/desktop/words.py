"""What the desktop client says, in a student's words. Pure: no Qt, no I/O.

The robot's activity (the service's one word, shared with the browser's header and jog pad),
the line of the student's file instead of the controller's step number, upload progress in
per cent, why a jog ended, and the name of each action in the activity log. Controller
errors are not here: their sentences and fixes live in `melfa.protocol.advice`, and the
server sends them ready to show.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from melfa.desktop.api import ApiError, CheckResult, ServerUnreachable
from melfa.desktop.messages import LinkStatus, RobotState

JOG_AXES = {"xyz": ("X", "Y", "Z", "A", "B", "C"), "tool": ("X", "Y", "Z", "A", "B", "C")}
FRAME_WORDS = {"xyz": "base", "tool": "tool", "joint": "joints"}


@dataclass(frozen=True)
class Loaded:
    """What this client loaded: the file's name and the controller's step -> file line map."""

    name: str
    step_lines: dict[int, int] = field(default_factory=dict)


def jog_label(frame: str, axis: int, direction: int) -> str:
    """The key's name: ``X+`` in the base or tool frame, ``J3-`` in joints.

    >>> jog_label("xyz", 0, 1), jog_label("joint", 2, -1), jog_label("tool", 2, -1)
    ('X+', 'J3−', 'Z−')
    """
    name = f"J{axis + 1}" if frame == "joint" else JOG_AXES.get(frame, JOG_AXES["xyz"])[axis]
    return f"{name}{'+' if direction > 0 else '−'}"


def jog_words(detail: str) -> str:
    """The server's jog detail (``xyz X+``) as a student reads it.

    >>> jog_words("xyz X+"), jog_words("tool Z-"), jog_words("joint J3+"), jog_words("")
    ('X+ (base)', 'Z- (tool)', 'J3+', '')
    """
    frame, _, axis = detail.partition(" ")
    if not axis:
        return detail
    return axis if frame == "joint" else f"{axis} ({FRAME_WORDS.get(frame, frame)})"


def file_line(step: int | None, loaded: Loaded | None) -> int | None:
    """The line of the loaded file the controller's step number stands for, if known.

    >>> file_line(50, Loaded("pick.MB4", {10: 1, 50: 5})), file_line(60, Loaded("p", {}))
    (5, None)
    """
    if not step or loaded is None:
        return None
    return loaded.step_lines.get(step)


def where_in_program(state: RobotState, loaded: Loaded | None) -> str:
    """``line 5 of pick.MB4``: the line of the student's file, never a bare step number.

    >>> s = RobotState.from_json({"line": 50, "program": "1"})
    >>> where_in_program(s, Loaded("pick.MB4", {50: 5}))
    'line 5 of pick.MB4'
    >>> where_in_program(s, None)
    'the line numbered 50 (the program was loaded elsewhere)'
    """
    line = file_line(state.line, loaded)
    if line is not None and loaded is not None:
        return f"line {line} of {loaded.name}"
    if state.line:
        return f"the line numbered {state.line} (the program was loaded elsewhere)"
    return ""


def activity_text(state: RobotState, loaded: Loaded | None) -> str:
    """What the robot does now, the same word the browser shows (docs/api.md ``activity``).

    >>> activity_text(RobotState.from_json({"activity": "jogging",
    ...                                     "activity_detail": "xyz X+"}), None)
    'Jogging X+ (base)'
    >>> activity_text(RobotState.from_json({"activity": "running", "line": 50}),
    ...               Loaded("pick.MB4", {50: 5}))
    'Running line 5 of pick.MB4'
    >>> activity_text(RobotState.from_json({"activity": "alarm",
    ...     "alarm": {"number": 2000, "code": "L2000", "message": "The servo is off."}}), None)
    'Alarm L2000'
    """
    activity = state.activity
    if activity == "uploading" or (not activity and state.busy):
        return "Sending a program to the robot…"
    if activity == "alarm" or (not activity and state.alarm is not None):
        return f"Alarm {state.alarm.code}" if state.alarm else "Alarm"
    if activity == "jogging":
        detail = jog_words(state.activity_detail)
        return f"Jogging {detail}".strip()
    if activity == "moving-to":
        return f"Moving to {state.activity_detail or 'a point'}"
    if activity == "running" or (not activity and state.running):
        where = where_in_program(state, loaded)
        return f"Running {where}".strip()
    if activity == "paused":
        where = where_in_program(state, loaded)
        return f"Paused at {where}: Run continues" if where else "Paused: Run continues"
    if activity == "moving":
        return "Robot moving (not started by melfa)"
    if activity == "offline" or state.link in (LinkStatus.LOST, LinkStatus.CLOSED):
        return "Robot not connected"
    return "Idle"


def upload_progress(sent: int, total: int) -> tuple[str, int]:
    """The status text and the per cent for a ``progress`` message (bytes of the upload).

    >>> upload_progress(0, 1724), upload_progress(862, 1724)
    (('Sending to the robot: 0 %', 0), ('Sending to the robot: 50 %', 50))
    >>> upload_progress(1724, 1724)
    ('Sent to the robot; the controller is checking it', 100)
    """
    percent = max(0, min(100, round(100 * sent / total))) if total else 0
    if total and sent >= total:
        return "Sent to the robot; the controller is checking it", 100
    return f"Sending to the robot: {percent} %", percent


JOG_END_WORDS = {
    "heartbeat lost": "the key's signal stopped reaching the server, so the arm stopped",
    "client disconnected": "the connection closed, so the arm stopped",
    "lease released": "control was given back",
    "lease lost": "control ended",
    "service closing": "the server is shutting down",
}


def jog_end_words(reason: str) -> str:
    """Why a jog ended, for the log.

    >>> jog_end_words("heartbeat lost")
    "the key's signal stopped reaching the server, so the arm stopped"
    >>> jog_end_words("stopped by ann"), jog_end_words("link lost")
    ('STOP pressed by ann', 'the robot link was lost')
    """
    if reason in JOG_END_WORDS:
        return JOG_END_WORDS[reason]
    if reason.startswith("stopped by "):
        return f"STOP pressed by {reason.removeprefix('stopped by ')}"
    if reason.startswith("taken over by "):
        return f"{reason.removeprefix('taken over by ')} took control"
    if reason.startswith("link "):
        return "the robot link was lost"
    if reason.startswith("lease ended"):
        return "control ended"
    return "the server ended it"


def control_text(state: RobotState, me: str) -> str:
    """Who holds control (the lease), since when, and the state of their connection.

    >>> control_text(RobotState.from_json({}), "ann")
    'Free: your first command takes it'
    >>> control_text(RobotState.from_json({"lease_holder": "ann"}), "ann")
    'You'
    >>> control_text(RobotState.from_json({"lease_holder": "bob",
    ...                                    "lease_state": "no connection"}), "ann")
    'bob — no connection'
    """
    holder = state.lease_holder
    if holder is None:
        return "Free: your first command takes it"
    text = "You" if holder == me else holder
    if state.lease_since is not None:
        text += f", since {state.lease_since.astimezone():%H:%M}"
    if holder != me and state.lease_state:
        text += f" — {state.lease_state}"
    return text


LINK_WORDS = {
    LinkStatus.CONNECTED: "Robot connected",
    LinkStatus.CONNECTING: "Connecting to the robot…",
    LinkStatus.RECONNECTING: "Robot link lost; reconnecting…",
    LinkStatus.LOST: "Robot link lost",
    LinkStatus.CLOSED: "Robot link closed",
    LinkStatus.UNKNOWN: "Robot link unknown",
}


def count(n: int, what: str) -> str:
    """
    >>> count(1, "line"), count(7, "line"), count(0, "point")
    ('1 line', '7 lines', '0 points')
    """
    return f"{n} {what}{'s' * (n != 1)}"


def diagnostic_lines(result: CheckResult, errors_only: bool = True) -> tuple[str, ...]:
    """``line:col  message`` for the dialog, program first, then points."""
    out: list[str] = []
    for where, diags in (("", result.program), ("points ", result.points)):
        for d in diags:
            if errors_only and d.severity.value != "error":
                continue
            out.append(f"{where}{d.line}:{d.column}  {d.message}")
    return tuple(out)


def sentence(text: str) -> str:
    """
    >>> sentence("wrong username or password"), sentence("Done.")
    ('Wrong username or password.', 'Done.')
    """
    text = text.strip()
    text = text[:1].upper() + text[1:]
    return text if not text or text[-1] in ".!?…" else text + "."


def describe_failure(exc: BaseException) -> tuple[str, tuple[str, ...]]:
    """A sentence for people (and diagnostic lines) for a failed call, naming whose fault:
    the API's message (already in the student's words) with the controller's code."""
    if isinstance(exc, ApiError):
        lines = tuple(f"{d.line}:{d.column}  {d.message}" for d in exc.diagnostics)
        code = f" (code {exc.error_code})" if exc.error_code else ""
        if exc.status == 503:
            return f"The robot link is down. {sentence(exc.message)}", lines
        if exc.status >= 500:
            return f"The server failed. {sentence(exc.message)}", lines
        return f"{sentence(exc.message)}{code}", lines
    if isinstance(exc, ServerUnreachable):
        return f"Cannot reach the server at {exc.url} ({exc.reason}). Is it running?", ()
    return "Something went wrong inside melfa desktop; the details are in its terminal.", ()


__all__ = [
    "JOG_END_WORDS",
    "LINK_WORDS",
    "Loaded",
    "activity_text",
    "control_text",
    "count",
    "describe_failure",
    "diagnostic_lines",
    "file_line",
    "jog_end_words",
    "jog_label",
    "jog_words",
    "sentence",
    "upload_progress",
    "where_in_program",
]
