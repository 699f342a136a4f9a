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
import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from melfa.link import LinkError
from melfa.protocol import PositionUnknown, RemoteProtocolError
from melfa.protocol.answers import RunStatus
from melfa.robot import ControllerError, Robot, RobotError
from melfa.service.clock import Clock
from melfa.service.config import ServiceConfig
from melfa.service.errors import LinkDown, ServiceClosed
from melfa.service.events import LinkStatus
from melfa.service.polling import PollCommand, Poller, PollResult, PositionUnknownRead
from melfa.service.posts import BusyChanged, LinkChanged, Polled, Post
from melfa.vocab.commands import Command

log = logging.getLogger(__name__)

IDLE_CHECK_S = 0.2
"""Without polling, how often a job waiting for the arm to stop reads the status (≥ 100 ms
while running [DOC S1 §3.3.3])."""


class Priority(enum.IntEnum):
    """Queue order (stop never queues)."""

    JOG = 1
    USER = 2


@dataclass
class Job:
    """One unit of work for the worker thread."""

    command: Command
    priority: Priority
    fn: Callable[[Robot], Any]
    future: concurrent.futures.Future[Any] = field(default_factory=concurrent.futures.Future)
    moves: bool = True
    busy: str | None = None
    """Shown in the state while the job runs (``upload``)."""


class Worker:
    """Owns the robot client. Public methods are thread-safe."""

    def __init__(
        self,
        connect: Callable[[], Robot],
        config: ServiceConfig,
        post: Callable[[Post], None],
        *,
        listeners: Callable[[], int],
        jog_view: Callable[[], tuple[bool, float]],
        clock: Clock,
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
        self._poller = Poller(config)
        self._last_poll_end = -1e9
        self._rtt: dict[str, float] = {}
        self._last_error = ""
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
            self._clock.notify(self._cond)

    def join(self, timeout: float | None = None) -> bool:
        self._thread.join(timeout)
        return not self._thread.is_alive()

    # ------------------------------------------------------------------ queue

    def submit(self, job: Job) -> concurrent.futures.Future[Any]:
        """Queue ``job``; it fails at once with `LinkDown` while the link is down."""
        if self._closing.is_set():
            job.future.set_exception(ServiceClosed("the robot service is closing"))
            return job.future
        if self.status is not LinkStatus.CONNECTED:
            job.future.set_exception(
                LinkDown(f"the robot link is {self.status.value}; {job.command.label} was not sent")
            )
            return job.future
        with self._cond:
            heapq.heappush(self._heap, (int(job.priority), next(self._seq), job))
            self._clock.notify(self._cond)
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
            self._clock.notify(self._cond)

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
        with self._clock.thread():
            self._serve()

    def _serve(self) -> None:
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
                    try:
                        self._poll()
                    except Exception as exc:  # nothing a reply does may end the worker
                        log.exception("robot worker: unexpected failure, reconnecting")
                        self._reconnect(f"unexpected failure: {exc}")
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
                self._clock.wait(self._cond, 0.5 if wait is None else wait)

    def _run(self, job: Job) -> None:
        if not job.future.set_running_or_notify_cancel():
            return
        robot = self.robot
        if robot is None:
            job.future.set_exception(
                LinkDown(f"the robot link is down; {job.command.label} was not sent")
            )
            return
        self.current = job
        if job.busy:
            self._post(BusyChanged(job.busy))
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
                self._post(BusyChanged(None))

    # ------------------------------------------------------------------ link

    def _set_status(self, status: LinkStatus, detail: str = "") -> None:
        if status is not self.status:
            self.status = status
            self._post(LinkChanged(status, detail))

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
        self._poller.reconnected()
        self._set_status(LinkStatus.CONNECTED, f"{why}: {robot.link.description}")
        return True

    def _reconnect(self, reason: str) -> None:
        """Reopen the link with exponential backoff until it works or the service closes."""
        self._drop_robot(graceful=False)
        if self._closing.is_set():
            return
        self._set_status(LinkStatus.RECONNECTING, reason)
        started = self._clock.now()
        delay = self.config.reconnect_initial_s
        while not self._closing.is_set():
            if self._pause(delay):
                return
            if self._open("reconnected"):
                return
            if (
                self._clock.now() - started > self.config.lost_after_s
                and self.status is not LinkStatus.LOST
            ):
                self._set_status(LinkStatus.LOST, self._last_error or reason)
            delay = min(delay * 2, self.config.reconnect_max_s)

    def _pause(self, seconds: float) -> bool:
        """Wait ``seconds`` on the clock, or less when the service closes (True then)."""
        with self._cond:
            if not self._closing.is_set():
                self._clock.wait(self._cond, seconds)
            return self._closing.is_set()

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
        now = self._clock.now()
        listening = self._listeners() > 0
        due = self._last_poll_end + (
            self.config.poll_floor_s if listening else self.config.idle_poll_s
        )
        if self._poller.program_running:
            due = max(due, self._last_poll_end + self.config.running_spacing_s)
        active, last_sent = self._jog_view()
        if active:
            # The JOG dead-man must be renewed within the watchdog: only poll when this
            # poll's round trip and the next JOG's fit in what is left of it.
            budget = self.config.jog_watchdog_s - self.config.jog_poll_margin_s
            command = self._poller.peek()
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
        return active and self._clock.now() - self._last_poll_end >= self.config.jog_poll_every_s

    def poll_while_moving(self, robot: Robot, timeout: float = 60.0) -> None:
        """In a job: wait until the arm stops (the status's RUN bit), reading the joints
        between checks (and the pose, until the tool offset is known), so snapshots keep
        flowing during the move: never a silent gap longer than one poll (a bare
        `Robot.wait_idle` would hold the line for the whole move). Without polling, only
        the status is read, every `IDLE_CHECK_S`."""
        polling = self.config.polling
        end = self._clock.now() + timeout
        while True:
            if RunStatus.RUNNING not in robot.dstate().status.run:
                return
            if self._clock.now() > end:
                raise RobotError(f"still moving after {timeout:g} s")
            self._pause(self.config.poll_floor_s if polling else IDLE_CHECK_S)
            if polling:
                self._poll(reconnect=False, command=PollCommand.JOINTS)
                if self._poller.tool_offset is None:
                    self._poll(reconnect=False, command=PollCommand.POSE)

    def _poll(self, *, reconnect: bool = True, command: PollCommand | None = None) -> None:
        """One poll request (the next of the cycle, or ``command``) and everything that can
        come of it: the one place a poll's answer or failure is handled. A dropped link
        reconnects (or, inside a job, fails the job); a refusal or a garbled answer skips
        this read."""
        robot = self.robot
        if robot is None:
            return
        if command is None:
            command = self._poller.take()
        started = self._clock.now()
        result: PollResult | None
        try:
            result = self._poller.read(robot, command)
        except LinkError as exc:
            self._last_poll_end = self._clock.now()
            if not reconnect:
                raise  # inside a job: the job fails and `_run` reconnects once
            self._reconnect(str(exc))
            return
        except PositionUnknown:
            result = PositionUnknownRead()  # ``****``: the origin is lost
        except (ControllerError, RemoteProtocolError, RobotError):
            result = None
        except Exception as exc:
            # A reply no parser expected: logged as it came, the line resynchronised.
            log.warning(
                "robot worker: the reply to %s was not understood (%s): %r",
                command,
                exc,
                robot.channel.last_reply,
            )
            result = None
            with contextlib.suppress(Exception):
                robot.channel.resync()
        finally:
            self.measure(command, self._clock.now() - started)
        self._last_poll_end = self._clock.now()
        self.polls += 1
        if result is not None:
            self._post(Polled(result))


__all__ = ["Job", "Priority", "Worker"]
