"""What a ROS node does with a `RobotService`, independent of the ROS client library.

`RosCore` runs on the service's event loop. A binding (the rospy node, the rosbridge
endpoint, later an rclpy node) gives it a `RosOutput` to publish through and a
`ParamSource` to read load texts from, and forwards to it:

- every ``execute_instruction`` string → `put_instruction` (handled strictly in arrival order
  by one task, through `melfa.service.ThesisMessages`);
- every service call → `call` → `ServiceReply(success, message)` (never raises: a refusal
  is ``success=False`` with the reason, whose fault it is included).

`stream` pumps the service's snapshots (and the thesis adapter's REQUEST answers) to the
output until the service closes.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from melfa.lang.encoding import decode_text
from melfa.lang.plan import plan_upload
from melfa.robot import ControllerError, RobotError, UploadReport
from melfa.ros import interface as ri
from melfa.ros.messages import BASE_FRAME, JointStateData, PoseData, StreamMessages
from melfa.service import (
    Actor,
    RobotService,
    ServiceError,
    StateSnapshot,
    ThesisMessages,
    ThesisOutput,
)
from melfa.service.service import describe_error
from melfa.service.thesis import MELFA, Dialect

log = logging.getLogger(__name__)


REFUSALS = (ServiceError, RobotError, ValueError)
"""A call refused for the caller's situation (no lease, servo off, a bad program, the
controller's refusal): answered, and logged at INFO; anything else is a fault (ERROR)."""


def log_level(exc: BaseException) -> int:
    """The log level of a failed call: a refusal is no error of the server's, but an alarm
    on the arm (the controller refused a motion) is what a ROS operator must see."""
    if isinstance(exc, ControllerError):
        return logging.ERROR
    return logging.INFO if isinstance(exc, REFUSALS) else logging.ERROR


class RosOutput(Protocol):
    """Where a binding publishes; called on the service's loop thread (keep it quick)."""

    def joint_states(self, message: JointStateData) -> None: ...

    def tool_pose_stamped(self, message: PoseData) -> None: ...

    def text(self, topic: str, text: str) -> None:
        """A ``std_msgs/String`` on ``topic`` (tool_pose, joint_state, execute_error)."""

    def log(self, level: int, text: str) -> None:
        """A line for the ROS log (``logging`` levels)."""


class ParamSource(Protocol):
    """The node's private parameters (``~program`` is ``/melfa/program``)."""

    def get(self, name: str) -> object | None: ...


@dataclass(frozen=True)
class ServiceReply:
    """A ``std_srvs/Trigger`` / ``SetBool`` response."""

    success: bool
    message: str


def _report(report: UploadReport) -> str:
    return (
        f"{report.items} lines, {report.bytes_sent} bytes in {report.requests} requests, "
        f"{report.seconds:.2f} s"
    )


class RosCore:
    """One ROS binding's view of the service, acting as ``actor``."""

    def __init__(
        self,
        service: RobotService,
        actor: Actor,
        output: RosOutput,
        params: ParamSource,
        *,
        frame_id: str = BASE_FRAME,
        max_rate_hz: float | None = None,
        dialect: Dialect = MELFA,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        if max_rate_hz is not None and max_rate_hz <= 0:
            raise ValueError("max_rate_hz must be positive (or None for every snapshot)")
        self.service = service
        self.actor = actor
        self.output = output
        self.params = params
        self.frame_id = frame_id
        self.max_rate_hz = max_rate_hz
        self._clock = clock
        self.dialect = dialect
        self.thesis = ThesisMessages(service, actor, dialect=dialect)
        self._instructions: asyncio.Queue[str] = asyncio.Queue()
        self._tasks: list[asyncio.Task[None]] = []
        self._stream: asyncio.Task[None] | None = None
        self.published = 0
        """Snapshots published (each as joint_states, tool_pose_stamped and the strings)."""
        self.instructions = 0
        self.errors = 0

    # ------------------------------------------------------------------ lifecycle

    def start(self, *, stream: bool = True) -> None:
        """Start handling instructions and publishing answers (on the service's loop);
        with ``stream`` also the state stream (else `start_stream` when first wanted: a
        state subscriber makes the service poll as fast as the line allows)."""
        self._tasks = [
            asyncio.create_task(self._handle_instructions(), name="ros-instructions"),
            asyncio.create_task(self._answers(), name="ros-answers"),
        ]
        if self.dialect.servo_on_connect:
            # The thesis's node switched the servo on whenever it connected to the robot.
            self._instructions.put_nowait(_SERVO_ON)
        if stream:
            self.start_stream()

    def start_stream(self) -> None:
        if self._stream is None or self._stream.done():
            self._stream = asyncio.create_task(self.stream(), name="ros-stream")

    async def stop_stream(self) -> None:
        task, self._stream = self._stream, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await task

    @property
    def streaming(self) -> bool:
        return self._stream is not None and not self._stream.done()

    async def close(self) -> None:
        """Stop the tasks; a move the thesis adapter is making finishes first."""
        await self.stop_stream()
        for task in self._tasks:
            task.cancel()
        for task in self._tasks:
            with contextlib.suppress(asyncio.CancelledError, Exception):
                await task
        self._tasks = []
        with contextlib.suppress(Exception):
            await self.thesis.close()

    # ------------------------------------------------------------------ topics

    async def put_instruction(self, text: str) -> None:
        """An ``execute_instruction`` message (handled in order, after the earlier ones)."""
        self._instructions.put_nowait(text)

    async def _handle_instructions(self) -> None:
        while True:
            text = await self._instructions.get()
            try:
                if text is _SERVO_ON:
                    await self.thesis.servo(True)
                    continue
                self.instructions += 1
                await self.thesis.feed(text)
            except Exception as exc:
                self.report(f"execute_instruction {text!r}", exc)

    def report(self, what: str, exc: BaseException) -> None:
        """A failure, on ``/execute_error`` and in the node's log (whose fault it is)."""
        self.errors += 1
        reason = describe_error(exc)
        self.output.log(log_level(exc), f"{what}: {reason}")
        self.output.text(ri.EXECUTE_ERROR, reason)

    async def _answers(self) -> None:
        """The thesis adapter's REQUEST answers and jog errors, on their topics."""
        with self.service.subscribe(ThesisOutput) as sub:
            async for event in sub:
                if isinstance(event, ThesisOutput) and event.actor == self.actor:
                    if event.topic == ri.EXECUTE_ERROR:
                        self.output.log(logging.INFO, f"jog step: {event.text}")
                    self.output.text(event.topic, event.text)

    async def stream(self) -> None:
        """Publish every snapshot (at most ``max_rate_hz``) until the service closes."""
        min_gap = 1.0 / self.max_rate_hz if self.max_rate_hz else 0.0
        last = -float("inf")
        with self.service.subscribe(StateSnapshot) as sub:
            async for event in sub:
                if not isinstance(event, StateSnapshot):
                    continue
                now = self._clock()
                if now - last < min_gap:
                    continue
                if self.publish_snapshot(event):
                    last = now

    def publish_snapshot(self, snapshot: StateSnapshot) -> bool:
        """Publish one snapshot; False when it holds no joints yet."""
        messages = StreamMessages.of(snapshot, self.frame_id)
        if messages.joint_states is None:
            return False
        self.output.joint_states(messages.joint_states)
        texts = self.dialect.streams_text
        if texts and messages.joint_state_text is not None:
            self.output.text(ri.JOINT_STATE_TEXT, messages.joint_state_text)
        if messages.tool_pose_stamped is not None:
            self.output.tool_pose_stamped(messages.tool_pose_stamped)
        if texts and messages.tool_pose_text is not None:
            self.output.text(ri.TOOL_POSE, messages.tool_pose_text)
        self.published += 1
        return True

    # ------------------------------------------------------------------ services

    async def call(
        self, name: str, data: bool | None = None, texts: dict[str, str] | None = None
    ) -> ServiceReply:
        """Run service ``name`` (see `melfa.ros.interface.SERVICES`); never raises. A
        failure is in the reply and in the node's log. ``texts`` (rosbridge's ``args``:
        ``program``, ``points``) are used instead of the parameters."""
        try:
            message = await self._call(name, data, texts or {})
        except Exception as exc:
            self.output.log(log_level(exc), f"service {name}: {describe_error(exc)}")
            return ServiceReply(False, describe_error(exc))
        return ServiceReply(True, message)

    async def _call(self, name: str, data: bool | None, texts: dict[str, str]) -> str:
        service, actor = self.service, self.actor
        if name == ri.LOAD_PROGRAM:
            program = self._text(ri.PROGRAM_PARAM, texts)
            plan = await asyncio.to_thread(plan_upload, program)
            report = await service.upload_program(actor, plan)
            return f"program loaded: {_report(report)}"
        if name == ri.LOAD_POINTS:
            points = self._text(ri.POINTS_PARAM, texts)
            plan = await asyncio.to_thread(plan_upload, None, points)
            report = await service.upload_points(actor, plan)
            return f"points loaded: {_report(report)}"
        if name == ri.LOAD_PROJECT:
            program = self._text(ri.PROGRAM_PARAM, texts)
            points = self._text(ri.POINTS_PARAM, texts, required=False)
            plan = await asyncio.to_thread(plan_upload, program, points)
            report = await service.load_project(actor, plan)
            return f"program and points loaded: {_report(report)}"
        if name == ri.RESET:
            await service.reset_alarm(actor)
            return "alarm reset"
        if name == ri.OVERRIDE:
            percent = self._override(texts)
            return f"override {await service.override(actor, percent)} %"
        if name == ri.STATE:
            return describe_state(service.want_state())
        if name == ri.RUN:
            await service.run(actor)
            return "program started"
        if name == ri.STOP:
            await service.stop(actor)
            return "stopped"
        if name == ri.DELETE:
            await service.delete(actor)
            return "program and points deleted"
        if name == ri.SERVO:
            on = bool(data)
            await service.servo(actor, on)
            return "servo on" if on else "servo off"
        raise LookupError(f"no service {name!r}; there are {', '.join(ri.SERVICE_BY_NAME)}")

    def _override(self, texts: dict[str, str]) -> int:
        value = texts.get(ri.OVERRIDE_PARAM, self.params.get(ri.OVERRIDE_PARAM))
        if value is None:
            raise LookupError(
                f"set the parameter ~{ri.OVERRIDE_PARAM} to a percentage first "
                f"(rosparam set /<node>/{ri.OVERRIDE_PARAM} 50)"
            )
        try:
            return int(str(value))
        except ValueError:
            raise ValueError(
                f"~{ri.OVERRIDE_PARAM} must be a whole percentage, not {value!r}"
            ) from None

    def _text(self, param: str, texts: dict[str, str], *, required: bool = True) -> str:
        """The text given in the call, of parameter ``~param``, or of the file named by
        ``~param_file`` (UTF-8 or Windows-1252, as the IDE reads files)."""
        if param in texts:
            return texts[param]
        value = self.params.get(param)
        if value is not None:
            if not isinstance(value, str):
                raise TypeError(f"parameter ~{param} must be a string (the text itself)")
            return value
        path = self.params.get(f"{param}_file")
        if path is not None:
            try:
                return decode_text(Path(str(path)).read_bytes())
            except OSError as exc:
                raise FileNotFoundError(
                    f"cannot read ~{param}_file {str(path)!r}: {exc.strerror}"
                ) from exc
        if not required:
            return ""
        raise LookupError(
            f"set the parameter ~{param} to the text (rosparam set --textfile FILE "
            f"/<node>/{param}) or ~{param}_file to a path on the node's machine first"
        )


_SERVO_ON = "\0servo-on"
"""Queued first in thesis mode: the servo goes on before any message is handled."""


def describe_state(state: StateSnapshot) -> str:
    """The ``state`` service's answer: one line a person can read."""
    parts = [f"link {state.link.value}"]
    if state.servo is not None:
        parts.append(f"servo {'on' if state.servo else 'off'}")
    if state.running is not None:
        running = f"running {state.program or 'program'}" if state.running else "not running"
        if state.running and state.line is not None:
            running += f" line {state.line}"
        parts.append(running)
    if state.override is not None:
        parts.append(f"override {state.override} %")
    if state.alarm is not None:
        parts.append(f"alarm {state.alarm.number}: {state.alarm.text}")
    else:
        parts.append("no alarm")
    if state.lease_holder:
        parts.append(f"lease {state.lease_holder}")
    return "; ".join(parts)


__all__ = ["ParamSource", "RosCore", "RosOutput", "ServiceReply", "describe_state"]
