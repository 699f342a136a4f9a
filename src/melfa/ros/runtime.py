"""The asyncio service in a background thread, for ROS client libraries that call back
from their own threads (rospy, rclpy executors).

`ServiceThread` starts an event loop in a daemon thread, builds and starts the
`RobotService` and a `RosCore` on it, and lets any thread hand it coroutines with
`submit` (``asyncio.run_coroutine_threadsafe``).
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import threading
from collections.abc import Callable, Coroutine
from typing import Any, TypeVar

from melfa.ros.core import ParamSource, RosCore, RosOutput
from melfa.service import Actor, RobotService, Role

T = TypeVar("T")

ROS_ACTOR = Actor("ros", Role.INSTRUCTOR, "ros-node")
"""Who the node acts as in the audit log and for the lease (it takes a free lease on its
first moving command, like a signed-in user)."""


class ServiceThread:
    """A `RobotService` and its `RosCore` running on a loop in their own thread."""

    def __init__(
        self,
        make_service: Callable[[], RobotService],
        output: RosOutput,
        params: ParamSource,
        *,
        actor: Actor = ROS_ACTOR,
        **core_options: Any,
    ) -> None:
        self._make_service = make_service
        self._output = output
        self._params = params
        self._actor = actor
        self._core_options = core_options
        self.loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self._run, name="melfa-ros-loop", daemon=True)
        self._ready: concurrent.futures.Future[RosCore] = concurrent.futures.Future()
        self._done: asyncio.Event | None = None
        self.service: RobotService | None = None
        self.core: RosCore | None = None

    def start(self, timeout: float = 30.0) -> RosCore:
        """Start the loop, the service and the core; returns the core."""
        self._thread.start()
        return self._ready.result(timeout)

    def _run(self) -> None:
        asyncio.set_event_loop(self.loop)
        try:
            self.loop.run_until_complete(self._main())
        finally:
            self.loop.close()

    async def _main(self) -> None:
        self._done = asyncio.Event()
        try:
            service = self._make_service()
            await service.start()
            core = RosCore(service, self._actor, self._output, self._params, **self._core_options)
            core.start()
        except BaseException as exc:
            self._ready.set_exception(exc)
            return
        self.service, self.core = service, core
        self._ready.set_result(core)
        await self._done.wait()
        await core.close()
        await service.close()

    def submit(self, coro: Coroutine[Any, Any, T]) -> concurrent.futures.Future[T]:
        """Run ``coro`` on the service's loop (from any thread)."""
        return asyncio.run_coroutine_threadsafe(coro, self.loop)

    def close(self, timeout: float = 15.0) -> None:
        """Close the core and the service, end the thread (safe twice)."""
        if not self._thread.is_alive():
            return
        done = self._done
        if done is not None:
            with contextlib.suppress(RuntimeError):
                self.loop.call_soon_threadsafe(done.set)
        self._thread.join(timeout)


__all__ = ["ROS_ACTOR", "ServiceThread"]
