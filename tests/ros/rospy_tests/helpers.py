"""Helpers of the rospy tests: inboxes for topics, waiting, publishers, service calls."""

from __future__ import annotations

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


_publishers: list[Any] = []


def instruction_publisher() -> Any:
    """A fresh /execute_instruction publisher connected to the node. The earlier ones are
    unregistered first: rospy shares one publisher per topic, and a connection to a node
    an earlier test ended would count as connected while messages go nowhere."""
    while _publishers:
        _publishers.pop().unregister()
    pub = rospy.Publisher("/execute_instruction", std_msgs.String, queue_size=100)
    _publishers.append(pub)
    assert wait_for(lambda: pub.get_num_connections() >= 1), "the node did not subscribe"
    return pub


def position(pose: Any) -> tuple[float, float, float]:
    p = pose.pose.position
    return (p.x, p.y, p.z)


def trigger(name: str, node: str = "melfa") -> Any:
    rospy.wait_for_service(f"/{node}/{name}", timeout=30)
    return rospy.ServiceProxy(f"/{node}/{name}", std_srvs.Trigger)()
