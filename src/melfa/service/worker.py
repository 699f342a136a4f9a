"""The one thread that talks to the robot: a priority queue of jobs, polling when idle,
reconnecting when the link drops.

datasette's single writer, on a thread: the sync `melfa.robot.Robot` runs only here, so
nothing else writes to the link, and the asyncio side awaits `concurrent.futures.Future`s.
Jobs run by priority (jog before user commands); polling runs only when no job waits.
Stop does not queue at all: `stop_now` is called from another thread and uses the client's
cross-thread stop, which puts STOP on the wire right behind the request in flight.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import enum
import heapq
import itertools
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from melfa.kin import Pose, fk, pose_inv, pose_mul
from melfa.link import LinkError
from melfa.protocol import RemoteProtocolError, State, error_text
from melfa.protocol.answers import JOINT_NAMES, POSE_NAMES, RunStatus, StopStatus
from melfa.robot import ControllerError, Robot, RobotError
from melfa.service.config import ServiceConfig
from melfa.service.errors import LinkDown
from melfa.service.events import Alarm, LinkStatus

Clock = Callable[[], float]
Post = Callable[..., None]


class Priority(enum.IntEnum):
    """Queue order (stop never queues)."""

    JOG = 1
    USER = 2


@dataclass
class Job:
    """One unit of work for the worker thread."""

    name: str
    priority: Priority
    fn: Callable[[Robot], Any]
    future: concurrent.futures.Future[Any] = field(default_factory=concurrent.futures.Future)
    moves: bool = True
    busy: str | None = None
    """Shown in the state while the job runs (``upload``)."""


@dataclass
class _JogView:
    active: bool = False
    last_sent: float = 0.0


class Worker:
    """Owns the robot client. Public methods are thread-safe."""

    def __init__(
        self,
        connect: Callable[[], Robot],
        config: ServiceConfig,
        post: Post,
        *,
        listeners: Callable[[], int],
        jog_view: Callable[[], tuple[bool, float]],
        clock: Clock = time.monotonic,
    ) -> None:
        self._connect = connect
        self.config = config
        self._post = post
        self._listeners = listeners
        self._jog_view = jog_view
        self._clock = clock
        self.robot: Robot | None = None
        self.status = LinkStatus.CONNECTING
        self._cond = threading.Condition()
        self._heap: list[tuple[int, int, Job]] = []
        self._seq = itertools.count()
        self._closing = threading.Event()
        self._first_attempt = threading.Event()
        self._thread = threading.Thread(target=self._main, name="melfa-service-worker", daemon=True)
        self.current: Job | None = None
        # polling
        self._cycle: list[str] = []
        self._cycle_no = 0
        self._last_poll_end = -1e9
        self._program_running = False
        self._rtt: dict[str, float] = {}
        self._joints: tuple[float, ...] | None = None
        self._tool_offset: Pose | None = None
        self._measured_joints: tuple[float, ...] | None = None
        self._joints_still = False
        self._error_texts: dict[int, str] = {}
        self.polls = 0

    # ------------------------------------------------------------------ lifecycle

    def start(self) -> None:
        self._thread.start()

    def wait_first_attempt(self, timeout: float | None = None) -> bool:
        return self._first_attempt.wait(timeout)

    def shutdown(self, error: BaseException) -> None:
        """Fail queued jobs with ``error``, let the job in flight finish, close the robot."""
        self._closing.set()
        self.cancel_queued(lambda job: True, error)
        with self._cond:
            self._cond.notify_all()

    def join(self, timeout: float | None = None) -> bool:
        self._thread.join(timeout)
        return not self._thread.is_alive()

    # ------------------------------------------------------------------ queue

    def submit(self, job: Job) -> concurrent.futures.Future[Any]:
        """Queue ``job``; it fails at once with `LinkDown` while the link is down."""
        if self._closing.is_set():
            from melfa.service.errors import ServiceClosed

            job.future.set_exception(ServiceClosed("the robot service is closing"))
            return job.future
        if self.status is not LinkStatus.CONNECTED:
            job.future.set_exception(
                LinkDown(f"the robot link is {self.status.value}; {job.name} was not sent")
            )
            return job.future
        with self._cond:
            heapq.heappush(self._heap, (int(job.priority), next(self._seq), job))
            self._cond.notify_all()
        return job.future

    def cancel_queued(self, which: Callable[[Job], bool], error: BaseException) -> list[Job]:
        """Remove queued (not running) jobs for which ``which`` is true; fail them."""
        with self._cond:
            keep = [entry for entry in self._heap if not which(entry[2])]
            dropped = [entry[2] for entry in self._heap if which(entry[2])]
            self._heap = keep
            heapq.heapify(self._heap)
        for job in dropped:
            if job.future.set_running_or_notify_cancel():
                job.future.set_exception(error)
        return dropped

    def queued(self) -> list[Job]:
        with self._cond:
            return [entry[2] for entry in sorted(self._heap)]

    def wake(self) -> None:
        with self._cond:
            self._cond.notify_all()

    def stop_now(self) -> None:
        """Send STOP from the calling thread, overtaking the request in flight."""
        robot = self.robot
        if robot is None:
            raise LinkDown(f"the robot link is {self.status.value}; STOP was not sent")
        robot.stop()

    def rtt(self, command: str) -> float:
        """Measured round trip of ``command`` (moving average), 0 until measured."""
        return self._rtt.get(command, 0.0)

    def measure(self, command: str, seconds: float) -> None:
        old = self._rtt.get(command)
        self._rtt[command] = seconds if old is None else 0.7 * old + 0.3 * seconds

    # ------------------------------------------------------------------ thread

    def _main(self) -> None:
        try:
            if not self._open("connecting"):
                self._first_attempt.set()
                self._reconnect("the first connection failed")
            self._first_attempt.set()
            while True:
                job = self._next()
                if job is None:
                    if self._closing.is_set():
                        break
                    self._poll()
                else:
                    self._run(job)
        finally:
            self._first_attempt.set()
            self._drop_robot(graceful=True)
            self._set_status(LinkStatus.CLOSED, "service closed")

    def _next(self) -> Job | None:
        """The next job, or None when it is time to poll (or to close)."""
        with self._cond:
            while True:
                if self._heap:
                    if self._jog_starved():
                        return None  # one poll between JOG renewals (see _poll_wait)
                    return heapq.heappop(self._heap)[2]
                if self._closing.is_set():
                    return None
                wait = self._poll_wait()
                if wait is not None and wait <= 0:
                    return None
                self._cond.wait(0.5 if wait is None else wait)

    def _run(self, job: Job) -> None:
        if not job.future.set_running_or_notify_cancel():
            return
        robot = self.robot
        if robot is None:
            job.future.set_exception(LinkDown(f"the robot link is down; {job.name} was not sent"))
            return
        self.current = job
        if job.busy:
            self._post("busy", job.busy)
        try:
            result = job.fn(robot)
        except BaseException as exc:
            job.future.set_exception(exc)
            if isinstance(exc, LinkError):
                self._reconnect(str(exc))
        else:
            job.future.set_result(result)
        finally:
            self.current = None
            if job.busy:
                self._post("busy", None)

    # ------------------------------------------------------------------ link

    def _set_status(self, status: LinkStatus, detail: str = "") -> None:
        if status is not self.status:
            self.status = status
            self._post("status", status, detail)

    def _open(self, why: str) -> bool:
        try:
            robot = self._connect()
        except (LinkError, RobotError, RemoteProtocolError, OSError, ValueError) as exc:
            self._last_error = str(exc)
            return False
        try:
            robot.connect()
        except (LinkError, RobotError, RemoteProtocolError, OSError) as exc:
            self._last_error = str(exc)
            with contextlib.suppress(Exception):
                robot.link.close()
            return False
        self.robot = robot
        self._tool_offset = None
        self._measured_joints = None
        self._set_status(LinkStatus.CONNECTED, f"{why}: {robot.link.description}")
        return True

    def _reconnect(self, reason: str) -> None:
        """Reopen the link with exponential backoff until it works or the service closes."""
        self._drop_robot(graceful=False)
        if self._closing.is_set():
            return
        self._set_status(LinkStatus.RECONNECTING, reason)
        started = self._clock()
        delay = self.config.reconnect_initial_s
        while not self._closing.is_set():
            if self._closing.wait(delay):
                return
            if self._open("reconnected"):
                return
            if (
                self._clock() - started > self.config.lost_after_s
                and self.status is not LinkStatus.LOST
            ):
                self._set_status(LinkStatus.LOST, getattr(self, "_last_error", reason))
            delay = min(delay * 2, self.config.reconnect_max_s)

    def _drop_robot(self, *, graceful: bool) -> None:
        robot, self.robot = self.robot, None
        if robot is None:
            return
        if graceful:
            robot.close()  # CNTLOFF, CLOSE, link closed; never raises
        else:
            with contextlib.suppress(Exception):
                robot.link.close()

    # ------------------------------------------------------------------ polling

    def _poll_wait(self) -> float | None:
        """Seconds until the next poll may start (≤ 0: now), None when not polling."""
        if not self.config.polling or self.robot is None:
            return None
        now = self._clock()
        listening = self._listeners() > 0
        due = self._last_poll_end + (
            self.config.poll_floor_s if listening else self.config.idle_poll_s
        )
        if self._program_running:
            due = max(due, self._last_poll_end + self.config.running_spacing_s)
        active, last_sent = self._jog_view()
        if active:
            # The JOG dead-man must be renewed within the watchdog: only poll when this
            # poll's round trip and the next JOG's fit in what is left of it.
            budget = self.config.jog_watchdog_s - self.config.jog_poll_margin_s
            command = self._peek_poll()
            need = (now - last_sent) + self.rtt(command) + self.rtt("JOG")
            # On a line too slow for any poll to fit (9600 baud: JPOSF alone is ~0.13 s),
            # poll anyway every `jog_poll_every_s`: the jog pauses for one poll, but the
            # views keep seeing the arm move instead of freezing until the key is let go.
            starved = now - self._last_poll_end >= self.config.jog_poll_every_s
            if need > budget and not starved:
                return 0.01
        return due - now

    def _jog_starved(self) -> bool:
        """A jog's renewals keep the queue busy and no poll fitted for
        `ServiceConfig.jog_poll_every_s`: someone watches, so poll now."""
        if not self.config.polling or self.robot is None or self._listeners() == 0:
            return False
        active, _ = self._jog_view()
        return active and self._clock() - self._last_poll_end >= self.config.jog_poll_every_s

    def _peek_poll(self) -> str:
        if not self._cycle:
            self._cycle = self._plan_cycle()
        return self._cycle[0]

    def _plan_cycle(self) -> list[str]:
        n = self._cycle_no
        self._cycle_no += 1
        plan = ["JPOSF"]
        moving = not self._joints_still
        # One kind of pose per phase, never alternating: while moving, computed from every
        # JPOSF once the tool offset is known (else measured by PPOSF every cycle); at
        # rest, measured every `pose_every` cycles.
        if (moving and self._tool_offset is None) or (
            not moving and n % self.config.pose_every == 0
        ):
            plan.append("PPOSF")
        if n % self.config.state_every == 0:
            plan.append("STATE")
        if n % self.config.hand_every == 0:
            plan.append("HNDSTS")
        return plan

    def poll_while_moving(self, robot: Robot, timeout: float = 60.0) -> None:
        """In a job: wait until the arm stops (the status's RUN bit), reading the joints
        between checks (and the pose, until the tool offset is known), so snapshots keep
        flowing during the move: never a silent gap longer than one poll (a bare
        `Robot.wait_idle` would hold the line for the whole move)."""
        if not self.config.polling:
            robot.wait_idle(timeout)
            return
        end = self._clock() + timeout
        while True:
            if RunStatus.RUNNING not in robot.dstate().status.run:
                return
            if self._clock() > end:
                raise RobotError(f"still moving after {timeout:g} s")
            self._closing.wait(self.config.poll_floor_s)
            self._poll(reconnect=False, command="JPOSF")
            if self._tool_offset is None:
                self._poll(reconnect=False, command="PPOSF")

    def _poll(self, *, reconnect: bool = True, command: str | None = None) -> None:
        """One poll request: the next of the cycle, or ``command``."""
        robot = self.robot
        if robot is None:
            return
        if command is None:
            command = self._peek_poll()
            self._cycle.pop(0)
        started = self._clock()
        update: dict[str, Any] = {}
        try:
            update = self._poll_once(robot, command)
        except LinkError as exc:
            self._last_poll_end = self._clock()
            if not reconnect:
                raise  # inside a job: the job fails and `_run` reconnects once
            self._reconnect(str(exc))
            return
        except (ControllerError, RemoteProtocolError, RobotError):
            update = {}
        finally:
            self.measure(command, self._clock() - started)
        self._last_poll_end = self._clock()
        self.polls += 1
        if update:
            self._post("poll", update)

    def _poll_once(self, robot: Robot, command: str) -> dict[str, Any]:
        if command == "JPOSF":
            position = robot.joints()
            joints = position.values(*JOINT_NAMES)
            update: dict[str, Any] = {"joints": joints}
            if position.override is not None:
                update["override"] = position.override
            if position.speed is not None:
                update["speed"] = position.speed
            update["moving"] = bool(position.speed) or (
                self._joints is not None and joints != self._joints
            )
            self._joints = joints
            self._joints_still = not update["moving"]
            # At rest where the last PPOSF was read, that measured pose stands: the one
            # computed from 2-decimal joints can differ from it by ~0.5 mm, and alternating
            # the two would make a still arm's pose flicker.
            if self._tool_offset is not None and joints != self._measured_joints:
                with contextlib.suppress(Exception):
                    pose = pose_mul(fk(joints), self._tool_offset)
                    update["pose"] = (pose.x, pose.y, pose.z, pose.a, pose.b, pose.c)
                    update["pose_measured"] = False
            return update
        if command == "PPOSF":
            position = robot.pose()
            values = position.values(*POSE_NAMES)
            update = {"pose": values, "pose_measured": True}
            if position.fl1 is not None and position.fl2 is not None:
                update["flags"] = (position.fl1, position.fl2)
            # Learn the offset only from joints read at rest: joints read mid-move and a
            # pose read after the stop would teach a wrong offset.
            if not position.speed and self._joints is not None and self._joints_still:
                with contextlib.suppress(Exception):
                    x, y, z, a, b, c = values
                    measured = Pose(x, y, z, a, b, c, position.fl1 or 7, position.fl2 or 0)
                    self._tool_offset = pose_mul(pose_inv(fk(self._joints)), measured)
                    self._measured_joints = self._joints
            return update
        if command == "STATE":
            return self._state_update(robot, robot.state())
        if command == "HNDSTS":
            fields = robot.request("HNDSTS").answer.split(";")
            hands = tuple(
                {"1": True, "2": False}.get(fields[i + 1]) if i + 1 < len(fields) else None
                for i in range(0, 24, 3)
            )
            return {"hands": hands}
        return {}

    def _state_update(self, robot: Robot, state: State) -> dict[str, Any]:
        run = state.status.run
        running = RunStatus.RUNNING in run
        self._program_running = running
        number = state.status.error
        alarm = None
        if number:
            text = self._error_texts.get(number)
            if text is None:
                try:
                    text = robot.error_text(number)
                except (ControllerError, RemoteProtocolError, RobotError):
                    text = error_text(number)
                self._error_texts[number] = text
            alarm = Alarm(number, text)
        stop = state.status.stop
        selected = StopStatus.PROGRAM_SELECT in stop
        return {
            "program": state.program,
            "line": state.line,
            "override": state.override,
            "servo": RunStatus.SERVO_ON in run,
            "running": running,
            # An EXEC move sets RUN with PROGRAM SELECT still on; a program clears it.
            "program_running": running and not selected,
            "paused": not running and StopStatus.STOP in stop and not selected,
            "alarm": alarm,
        }


__all__ = ["Job", "Priority", "Worker"]
