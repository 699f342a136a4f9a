"""What the desktop client says, in a student's words. Pure: no Qt, no I/O.

The robot's activity, why a jog ended and the link's state come as codes and are said in the
words of `melfa.vocab` (the browser shows the same words from the served vocabulary); here
is what only this client adds: the line of the student's file instead of the controller's
step number, upload progress in per cent, who holds control. Controller errors are not
here: their sentences and fixes live in `melfa.protocol.advice`, and the server sends them
ready to show.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from melfa.desktop.api import ApiError, CheckResult, ServerUnreachable
from melfa.live.messages import QueueOut, StateOut
from melfa.protocol import JOINT_NAMES, POSE_NAMES
from melfa.vocab.activity import Activity, jog_detail, said, where
from melfa.vocab.lease import CONTROL_WORDS, HolderState
from melfa.vocab.link import LINK_UNKNOWN, LINK_WORDS, LinkStatus
from melfa.vocab.queue import QUEUE_WORDS, EntryState

JOG_AXES = {"xyz": POSE_NAMES, "tool": POSE_NAMES, "joint": JOINT_NAMES}


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
    name = JOG_AXES.get(frame, POSE_NAMES)[axis]
    return f"{name}{'+' if direction > 0 else '−'}"


def file_line(step: int | None, loaded: Loaded | None) -> int | None:
    """The line of the loaded file the controller's step number stands for, if known.

    >>> file_line(50, Loaded("pick.MB4", {10: 1, 50: 5})), file_line(60, Loaded("p", {}))
    (5, None)
    """
    if not step or loaded is None:
        return None
    return loaded.step_lines.get(step)


def where_in_program(state: StateOut, loaded: Loaded | None) -> str:
    """``line 5 of pick.MB4``: the line of the student's file, never a bare step number.

    >>> s = state_of(line=50, program="1")
    >>> where_in_program(s, Loaded("pick.MB4", {50: 5}))
    'line 5 of pick.MB4'
    >>> where_in_program(s, None)
    'line numbered 50'
    """
    line = file_line(state.line, loaded)
    if line is not None and loaded is not None:
        return where(line=line, file=loaded.name)
    return where(step=state.line)


def activity_text(state: StateOut, loaded: Loaded | None) -> str:
    """What the robot does now, in the sentence the browser shows too (`melfa.vocab.activity`).

    >>> activity_text(state_of(activity="jogging", activity_detail="xyz X+"), None)
    'Jogging X+ (base)'
    >>> activity_text(state_of(activity="running", line=50), Loaded("pick.MB4", {50: 5}))
    'Running line 5 of pick.MB4'
    >>> activity_text(state_of(activity="alarm", alarm={"number": 2000, "text": "Servo off",
    ...     "code": "L2000", "message": "The servo is off."}), None)
    'Alarm L2000'
    """
    activity = state.activity
    if activity in (Activity.RUNNING, Activity.PAUSED):
        detail = where_in_program(state, loaded)
    elif activity is Activity.JOGGING:
        detail = jog_detail(state.activity_detail)
    elif activity is Activity.ALARM:
        detail = state.alarm.code if state.alarm else ""
    else:
        detail = state.activity_detail
    return said(activity, detail)


def state_of(**fields: object) -> StateOut:
    """A snapshot with these fields and nothing known of the rest (for examples and tests)."""
    empty: dict[str, object] = dict.fromkeys(
        ("joints", "pose", "flags", "servo", "running", "moving", "line", "override", "speed",
         "alarm", "busy", "lease_holder"),
    )  # fmt: skip
    base = {"seq": 0, "at": "2026-11-24T09:00:00Z", "link": "connected", "pose_measured": False,
            "program": "", "hands": [], "jogging": False, **empty}  # fmt: skip
    return StateOut.model_validate({**base, **fields})


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


_HOLDER_STATES = {h.value: h for h in HolderState}


def control_text(state: StateOut, me: str, queued: bool = False) -> str:
    """Who holds control (the lease), since when, and the state of their connection, in
    the words of the browser's header (`melfa.vocab.lease.CONTROL_WORDS`); ``queued``:
    someone waits in the lab robot's queue, which alone gives free control.

    >>> control_text(state_of(), "ann")
    'free — the first to move the robot takes it'
    >>> control_text(state_of(), "ann", queued=True)
    'by the queue — while anyone waits, the queue gives it in turn'
    >>> control_text(state_of(lease_holder="ann"), "ann")
    'you'
    >>> control_text(state_of(lease_holder="bob", lease_state="no connection"), "ann")
    'bob · no connection'
    """
    w = CONTROL_WORDS
    holder = state.lease_holder
    if holder is None:
        return f"{w.by_queue} — {w.queue_gives}" if queued else f"{w.free} — {w.first_takes}"
    text = w.you if holder == me else holder
    if state.lease_since is not None:
        text += " " + w.since.format(time=f"{state.lease_since.astimezone():%H:%M}")
    connection = _HOLDER_STATES.get(state.lease_state or "")
    if holder != me and connection is not None and connection is not HolderState.CONNECTED:
        text += f" · {connection.words}"
    return text


def link_words(status: LinkStatus | None) -> str:
    """The link's state in the student's words (None: not known yet).

    >>> link_words(LinkStatus.LOST), link_words(None)
    ('Robot link lost', 'Robot link unknown')
    """
    return LINK_WORDS[status] if status is not None else LINK_UNKNOWN


def count(n: int, what: str) -> str:
    """
    >>> count(1, "line"), count(7, "line"), count(0, "point")
    ('1 line', '7 lines', '0 points')
    """
    return f"{n} {what}{'s' * (n != 1)}"


def diagnostic_lines(result: CheckResult, errors_only: bool = True) -> tuple[str, ...]:
    """``line:col  message`` for the dialog, program first, then points."""
    out: list[str] = []
    for part, diags in (("", result.program), ("points ", result.points)):
        for d in diags:
            if errors_only and d.severity.value != "error":
                continue
            out.append(f"{part}{d.line}:{d.column}  {d.message}")
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
    "Loaded",
    "activity_text",
    "control_text",
    "count",
    "describe_failure",
    "diagnostic_lines",
    "file_line",
    "jog_label",
    "link_words",
    "sentence",
    "state_of",
    "upload_progress",
    "where_in_program",
]


def queue_line(queue: QueueOut, me: str) -> tuple[str, bool]:
    """The lab robot's queue in one line for the status bar, and whether the arm is offered
    to ``me`` now (the window then shows its claim button); the words are the browser's
    panel's (`melfa.vocab.queue.QUEUE_WORDS`).

    >>> from datetime import datetime, UTC
    >>> at = datetime(2026, 11, 27, 9, 0, tzinfo=UTC)
    >>> entry = dict(user="ann", position=1, state="offered", estimate=at, offer_ends=at)
    >>> q = QueueOut(target="lab", now=at, active=True, paused=False, attended=False,
    ...              turn=None, entries=[entry], claim_s=60, turn_s=240, at_turn_end="stop")
    >>> queue_line(q, "ann")
    ('Lab robot queue · the arm is offered to you: claim it now', True)
    >>> queue_line(q, "bob")
    ('Lab robot queue · 1 waiting', False)
    >>> bob = dict(entry, user="bob", position=2, state="waiting", offer_ends=None,
    ...            gate="cell-changed")  # the lab's cell was changed since bob's passed
    >>> line, _ = queue_line(QueueOut(**{**q.model_dump(), "entries": [entry, bob]}), "bob")
    >>> line.split(" · ")[-1]
    'your queued program must pass pre-flight again (Pre-flight, in the IDE)'
    """
    w = QUEUE_WORDS
    if not queue.active:
        return f"{w.title} · {w.empty}", False
    parts = [f"{w.title} · {w.waiting.format(count=len(queue.entries))}"]
    turn = queue.turn
    if turn is not None:
        who = w.you if turn.user == me else turn.user
        left = w.line_turn.format(user=who, minutes=round(turn.left_s / 60))
        parts.insert(0, f"{w.at_arm}: {left}")
    mine = next((e for e in queue.entries if e.user == me), None)
    if mine is not None and mine.state is EntryState.OFFERED:
        return f"{w.title} · {w.line_offered}", True
    if mine is not None:
        wait = max(0, round((mine.estimate - queue.now).total_seconds() / 60))
        parts.append(w.line_place.format(position=mine.position, minutes=wait))
        if mine.gate is not None:  # the arm would refuse it at the turn: say so now
            parts.append(w.line_preflight)
    return " · ".join(parts), False
