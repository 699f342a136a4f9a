"""Helpers of the rospy tests: inboxes for topics, waiting, publishers, service calls."""

from __future__ import annotations

import select
import socket
import threading
import time
from collections.abc import Callable
from typing import Any

import pytest

rospy: Any = pytest.importorskip("rospy", reason="ROS 1 runs under scripts/ros-env only")
std_msgs: Any = pytest.importorskip("std_msgs.msg")
std_srvs: Any = pytest.importorskip("std_srvs.srv")


class Inbox:
    """Messages of one topic (rospy calls back from its own threads)."""

    def __init__(self, topic: str, kind: Any) -> None:
        self.items: list[Any] = []
        self._lock = threading.Lock()
        self.subscriber = rospy.Subscriber(topic, kind, self._put, queue_size=1000)

    def _put(self, message: Any) -> None:
        with self._lock:
            self.items.append(message)

    def last(self) -> Any:
        with self._lock:
            return self.items[-1] if self.items else None

    def snapshot(self) -> list[Any]:
        with self._lock:
            return list(self.items)

    def close(self) -> None:
        self.subscriber.unregister()


def wait_for(predicate: Callable[[], bool], timeout: float = 30.0) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.02)
    return predicate()


_publisher: list[Any] = []


def instruction_publisher() -> Any:
    """The /execute_instruction publisher, connected to the node now running.

    One publisher for the whole run, never unregistered: unregistering the last publisher of
    a topic and creating a new one races rospy's unregistration from the master against the
    new registration, and the master can end up with no publisher at all ("the node did not
    subscribe" on a fresh machine's first run). A connection to a node an earlier test ended
    is not counted: its socket reads end-of-file."""
    if not _publisher:
        _publisher.append(rospy.Publisher("/execute_instruction", std_msgs.String, queue_size=100))
    pub = _publisher[0]
    assert wait_for(lambda: live_connections(pub) >= 1), "the node did not subscribe"
    return pub


def live_connections(pub: Any) -> int:
    """Subscribers still there: a subscriber never writes after its header, so a socket
    that reads end-of-file belongs to a node that went away."""
    count = 0
    for connection in list(pub.impl.connections):
        sock = getattr(connection, "socket", None)
        if sock is None:
            continue
        try:
            readable, _, _ = select.select([sock], [], [], 0)
            if readable and sock.recv(1, socket.MSG_PEEK) == b"":
                continue
        except OSError:
            continue
        count += 1
    return count


def position(pose: Any) -> tuple[float, float, float]:
    p = pose.pose.position
    return (p.x, p.y, p.z)


def trigger(name: str, node: str = "melfa") -> Any:
    rospy.wait_for_service(f"/{node}/{name}", timeout=30)
    return rospy.ServiceProxy(f"/{node}/{name}", std_srvs.Trigger)()
