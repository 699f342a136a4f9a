"""The thesis's string control messages, driving the service (appendix 9.1, §4.3.3–4.3.5).

Clients of the thesis (its rqt plugin, its web page, ``rostopic pub``) send strings on the
``execute_instruction`` topic. `ThesisMessages.feed` takes those strings and keeps the
thesis's state machine:

====  ==========================  ===========================================================
S0    idle                        expects a control message
S1    single instruction          the next message is one statement → EXEC, back to S0
S2    receiving program           lines until ``---LOAD PROGRAM END---`` → upload, S0
S3    receiving points            lines until ``---LOAD POINTS END---`` → upload, S0
S4    jogging                     ``---MOV TOOL ±X/Y/Z---[timestamp]`` step moves in the tool
                                  frame; any other message leaves S4 (after the move running)
====  ==========================  ===========================================================

Jog rule (§4.3.5, appendix 9.2): a move message is carried out only if its timestamp (Unix
seconds, optional, default: when it arrived) is later than the end of the last finished move;
messages that piled up while the tool moved are dropped, never queued.

``---REQUEST TOOL POSE---`` / ``---REQUEST JOINT STATE---`` publish `ThesisOutput` events on
topics ``tool_pose`` "(x,y,z,roll,pitch,yaw)" and ``joint_state`` "(j1,j2,j3,j4,j5,j6)". The
thesis's node (S7) sent metres and radians; so does this adapter unless ``si_units=False``.
The PDF rendered ``---`` as an em dash, so ``—RUN PROGRAM—`` is accepted too.
``---OPEN TOOL---`` / ``---CLOSE TOOL---`` (the thesis's spacebar, §6.9.2; its message
names are not printed, so these are melfa's) open and close hand 1.

``---MOVE TOOL STATE---`` followed by ``(x,y,z,a,b,c)`` (mm and degrees, what the thesis's
page sends from a point's "Move" button) moves there in a straight line (S5).
``---CONNECT FOR LOAD---``, ``---CONNECT FOR EXECUTE---`` and ``---DISCONNECT---`` change
nothing, as in the thesis's node.

A message that makes no sense in the current state raises `ThesisMessageError` and returns
the machine to S0 (S7 did the same, printing the error).

Two dialects (`Dialect`): `MELFA` (the default for new clients) and `THESIS`, which
reproduces the thesis's execute node (``src/nodes/execute_node.cpp`` on its ``tfg-biel``
branch) for its unmodified clients: answers ``x,y,z,r,p,y`` without parentheses, jogs
20 mm along the base frame (+Z up), switches the servo on when it connects and before each
jog session, and off when the jog session ends (the thesis's test 7.1.4). docs/ros.md lists
every message and where the two differ.
"""

from __future__ import annotations

import asyncio
import enum
import math
import re
import time
from collections.abc import Callable
from dataclasses import dataclass

from melfa.lang.plan import plan_upload
from melfa.protocol import POSE_NAMES
from melfa.service.errors import ThesisMessageError
from melfa.service.events import Actor, JogFrame, ThesisOutput
from melfa.service.service import RobotService, describe_error
from melfa.service.servo import ServoPolicy


class ThesisState(enum.Enum):
    S0 = "idle"
    S1 = "single instruction"
    S2 = "receiving program"
    S3 = "receiving points"
    S4 = "jogging"
    S5 = "waiting for a pose to move to"


_DASH = r"(?:-{3}|[—–])"
_CONTROL = re.compile(
    rf"^{_DASH}\s*(?P<name>[A-Z][A-Z +\-]*?)\s*{_DASH}\s*(?P<stamp>\d+(?:\.\d+)?)?$"
)

MOVES: dict[str, tuple[int, int]] = {
    f"MOV TOOL {sign}{axis}": (index, 1 if sign == "+" else -1)
    for index, axis in enumerate(POSE_NAMES[:3])
    for sign in "+-"
}
"""Move messages → (tool axis 0–2, direction), in the thesis's order of checking."""

SIMPLE = frozenset(
    {
        "SINGLE INSTRUCTION",
        "LOAD PROGRAM BEGIN",
        "LOAD PROGRAM END",
        "LOAD POINTS BEGIN",
        "LOAD POINTS END",
        "RUN PROGRAM",
        "DELETE",
        "REQUEST TOOL POSE",
        "REQUEST JOINT STATE",
        "MOVE TOOL STATE",
        "MOVE JOINT STATE",
        "OPEN TOOL",
        "CLOSE TOOL",
        "CONNECT FOR LOAD",
        "CONNECT FOR EXECUTE",
        "DISCONNECT",
    }
)

HARMLESS = frozenset({"CONNECT FOR LOAD", "CONNECT FOR EXECUTE", "DISCONNECT"})
"""The thesis's node returned on these without doing anything (it connected per message)."""

_POSE = re.compile(r"^\(?\s*([^(),]+(?:,[^(),]+){5})\s*\)?")


@dataclass(frozen=True)
class Dialect:
    """How the control messages behave: melfa's defaults or the thesis's node exactly."""

    name: str
    parentheses: bool
    """Answers as ``(a,b,c)`` (appendix 9.1) or ``a,b,c`` (what the node really sent)."""
    jog_frame: JogFrame
    jog_step_mm: float | None
    """Step of ``MOV TOOL`` (None: `RobotSettings.jog_step_mm`)."""
    servo_on_connect: bool
    """Switch the servo on when the client connects, before each jog session, and off
    when the session ends, as the thesis's ``Melfa::connect``/``disconnect`` did."""
    streams_text: bool
    """Publish ``tool_pose``/``joint_state`` with every state update (else only when
    requested, as the thesis did)."""


MELFA = Dialect("melfa", True, JogFrame.TOOL, None, False, True)
THESIS = Dialect("thesis", False, JogFrame.XYZ, 20.0, True, False)
DIALECTS = {d.name: d for d in (MELFA, THESIS)}


def dialect_named(name: str) -> Dialect:
    """`MELFA` or `THESIS` by name; a clear error otherwise."""
    found = DIALECTS.get(name.strip().lower())
    if found is None:
        raise ValueError(f"mode {name!r} is not one of {', '.join(DIALECTS)}")
    return found


def parse_pose(message: str) -> tuple[float, ...]:
    """X, Y, Z, A, B, C of ``(x,y,z,a,b,c)`` (parentheses optional; a trailing ``(7,0)`` is
    ignored).

    >>> parse_pose("(417.61,16.40,180.00,180.00,0.00,180.00)")
    (417.61, 16.4, 180.0, 180.0, 0.0, 180.0)
    """
    match = _POSE.match(message.strip())
    if match is None:
        raise ThesisMessageError(f"{message.strip()[:60]!r} is not a pose (x,y,z,a,b,c)")
    try:
        return tuple(float(v) for v in match[1].split(","))
    except ValueError:
        raise ThesisMessageError(
            f"{message.strip()[:60]!r} is not a pose: six numbers (x,y,z,a,b,c) are needed"
        ) from None


def parse_control(message: str) -> tuple[str, float | None] | None:
    """``(name, timestamp)`` of a control message, None for an information message.

    >>> parse_control("---MOV TOOL +X---1468360644")
    ('MOV TOOL +X', 1468360644.0)
    >>> parse_control("—LOAD PROGRAM BEGIN—")
    ('LOAD PROGRAM BEGIN', None)
    >>> parse_control("10 MOV P1") is None
    True
    """
    match = _CONTROL.match(message.strip())
    if match is None:
        return None
    name = " ".join(match["name"].split())
    if name not in SIMPLE and name not in MOVES:
        raise ThesisMessageError(f"unknown control message {message.strip()!r}")
    stamp = match["stamp"]
    return name, float(stamp) if stamp is not None else None


def format_tuple(values: tuple[float, ...], *, parentheses: bool = True) -> str:
    """The thesis's "(a,b,c)" form, or "a,b,c" (six significant digits, like C++'s
    ``ostream``).

    >>> format_tuple((0.4, 0.0, 1.5707963), parentheses=False)
    '0.4,0,1.5708'
    """
    text = ",".join(f"{v:.6g}" for v in values)
    return f"({text})" if parentheses else text


class ThesisMessages:
    """Feed thesis strings; it drives ``service`` on behalf of ``actor``."""

    def __init__(
        self,
        service: RobotService,
        actor: Actor,
        *,
        si_units: bool = True,
        hand: int = 1,
        dialect: Dialect = MELFA,
        servo: ServoPolicy = ServoPolicy.TURN_ON,
        wall_clock: Callable[[], float] = time.time,
    ) -> None:
        """``servo``: what a move (jog, ``MOVE TOOL STATE``, run) does with the servo off
        (`melfa.service.servo`): a message asking to move is the operator asking, and a
        topic cannot ask back, so by default the servo is switched on (audited)."""
        self.service = service
        self.actor = actor
        self.si_units = si_units
        self.dialect = dialect
        self.servo_policy = servo
        self.hand = hand
        self._wall = wall_clock
        self.state = ThesisState.S0
        self._lines: list[str] = []
        self._pending: dict[tuple[int, int], float] = {}
        self._last_finished = -math.inf
        self._task: asyncio.Task[None] | None = None
        self.dropped = 0
        """Move messages dropped by the timestamp rule."""
        self.moves = 0
        self.errors: list[BaseException] = []

    async def feed(self, message: str) -> str | None:
        """Handle one message; returns the published text for REQUEST messages."""
        try:
            control = parse_control(message)
        except ThesisMessageError:
            await self._reset()
            raise
        if control is None:
            return await self._information(message)
        name, stamp = control
        if name in HARMLESS:
            return None
        if name in MOVES:
            if self.state not in (ThesisState.S0, ThesisState.S4):
                await self._reset()
                raise ThesisMessageError(f"{name} while {self.state.value} ({self.state.name})")
            if self.state is ThesisState.S0 and self.dialect.servo_on_connect:
                await self.servo(True)
            self.state = ThesisState.S4
            self._queue_move(MOVES[name], stamp)
            return None
        if name in ("OPEN TOOL", "CLOSE TOOL") and self.state in (ThesisState.S0, ThesisState.S4):
            await self._join_moves()
            await self.service.hand(self.actor, name == "OPEN TOOL", self.hand)
            return None
        if self.state is ThesisState.S4:
            await self._join_moves()
            self.state = ThesisState.S0
            if self.dialect.servo_on_connect:
                await self.servo(False)
        if self.state is ThesisState.S2 and name == "LOAD PROGRAM END":
            lines, self._lines, self.state = self._lines, [], ThesisState.S0
            plan = await asyncio.to_thread(plan_upload, "\n".join(lines))
            await self.service.upload_program(self.actor, plan)
            return None
        if self.state is ThesisState.S3 and name == "LOAD POINTS END":
            lines, self._lines, self.state = self._lines, [], ThesisState.S0
            plan = await asyncio.to_thread(plan_upload, None, "\n".join(lines))
            await self.service.upload_points(self.actor, plan)
            return None
        if self.state is not ThesisState.S0:
            state = self.state
            await self._reset()
            raise ThesisMessageError(f"{name} makes no sense while {state.value} ({state.name})")
        return await self._command(name)

    async def _command(self, name: str) -> str | None:
        if name == "SINGLE INSTRUCTION":
            self.state = ThesisState.S1
        elif name == "LOAD PROGRAM BEGIN":
            self._lines, self.state = [], ThesisState.S2
        elif name == "LOAD POINTS BEGIN":
            self._lines, self.state = [], ThesisState.S3
        elif name == "RUN PROGRAM":
            await self.service.run(self.actor, servo=self.servo_policy)
        elif name in ("MOVE TOOL STATE", "MOVE JOINT STATE"):
            self.state = ThesisState.S5
        elif name == "DELETE":
            await self.service.delete(self.actor)
        elif name == "REQUEST TOOL POSE":
            pose = await self.service.read_pose(self.actor)
            if self.si_units:
                pose = (*(v / 1000 for v in pose[:3]), *(math.radians(v) for v in pose[3:]))
            return self._publish("tool_pose", self._format(pose))
        elif name == "REQUEST JOINT STATE":
            joints = await self.service.read_joints(self.actor)
            if self.si_units:
                joints = tuple(math.radians(v) for v in joints)
            return self._publish("joint_state", self._format(joints))
        else:
            raise ThesisMessageError(f"{name} makes no sense while idle (S0)")
        return None

    async def _information(self, message: str) -> str | None:
        if self.state is ThesisState.S1:
            self.state = ThesisState.S0
            if self.dialect.servo_on_connect:
                await self.servo(True)
            await self.service.exec(self.actor, message)
            return None
        if self.state is ThesisState.S5:
            self.state = ThesisState.S0
            pose = parse_pose(message)
            if self.dialect.servo_on_connect:
                await self.servo(True)
            await self.service.move_to(self.actor, pose, linear=True, servo=self.servo_policy)
            return None
        if self.state in (ThesisState.S2, ThesisState.S3):
            self._lines.append(message.rstrip("\r\n"))
            return None
        state = self.state
        await self._reset()
        raise ThesisMessageError(
            f"{message.strip()[:40]!r} is not a control message, and nothing was announced "
            f"while {state.value} ({state.name})"
        )

    def _format(self, values: tuple[float, ...]) -> str:
        clean = tuple(0.0 if abs(v) < 1e-12 else v for v in values)
        return format_tuple(clean, parentheses=self.dialect.parentheses)

    async def servo(self, on: bool) -> None:
        """Servo on or off as the thesis's connect/disconnect did (nothing when it already
        is: the state stream knows)."""
        if self.service.state.servo is on:
            return
        await self.service.servo(self.actor, on)

    def _publish(self, topic: str, text: str) -> str:
        self.service.publish(ThesisOutput(actor=self.actor, topic=topic, text=text))
        return text

    # ------------------------------------------------------------------- jog (S4)

    def _queue_move(self, move: tuple[int, int], stamp: float | None) -> None:
        when = self._wall() if stamp is None else stamp
        if when <= self._last_finished:
            self.dropped += 1
            return
        if move in self._pending:
            self.dropped += 1  # superseded by a newer request for the same move
        self._pending[move] = max(self._pending.get(move, -math.inf), when)
        if self._task is None or self._task.done():
            self._task = asyncio.create_task(self._jog_loop(), name="thesis-jog")

    async def _jog_loop(self) -> None:
        """Appendix 9.2: while a requested move is newer than the last finished move, do
        it (in the thesis's order), then note when it finished."""
        while True:
            due = [
                m for m in MOVES.values() if self._pending.get(m, -math.inf) > self._last_finished
            ]
            stale = [m for m in self._pending if m not in due]
            for move in stale:
                del self._pending[move]
                self.dropped += 1
            if not due:
                return
            axis, direction = due[0]
            del self._pending[due[0]]
            try:
                await self.service.jog_step(
                    self.actor,
                    self.dialect.jog_frame,
                    axis,
                    direction,
                    wait=True,
                    servo=self.servo_policy,
                    step_mm=self.dialect.jog_step_mm,
                )
                self.moves += 1
            except Exception as exc:
                self.errors.append(exc)
                self._publish("execute_error", describe_error(exc))
            self._last_finished = self._wall()

    async def _join_moves(self) -> None:
        if self._task is not None:
            await self._task
            self._task = None

    async def _reset(self) -> None:
        await self._join_moves()
        self._lines = []
        self._pending.clear()
        self.state = ThesisState.S0

    async def close(self) -> None:
        """Wait for a move in progress; back to S0."""
        await self._reset()


__all__ = [
    "DIALECTS",
    "MELFA",
    "MOVES",
    "THESIS",
    "Dialect",
    "ThesisMessages",
    "ThesisState",
    "dialect_named",
    "format_tuple",
    "parse_control",
    "parse_pose",
]
