"""A real ROS 1 master on loopback and the `melfa ros` node on the virtual controller.

Runs only where Debian's rospy imports (`scripts/ros-env pytest tests/ros/rospy_tests`);
elsewhere the tests skip. roscore, rosmaster and rosout run in their own process group,
which is always ended, whatever the tests did.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

rospy: Any = pytest.importorskip("rospy", reason="ROS 1 runs under scripts/ros-env only")
rosgraph: Any = pytest.importorskip("rosgraph")

# roscore and the node are ended with Ctrl-C (SIGINT): a suite started in the background
# inherits SIGINT ignored and would pass that on (see tests/conftest.py).
signal.signal(signal.SIGINT, signal.default_int_handler)

START_TIMEOUT_S = 60.0
ROS_DEPRECATIONS = "ignore::DeprecationWarning:(rospy|rosgraph|genpy|roslib|rospkg)"
"""Noetic's Python code uses APIs Python 3.11 deprecates (``notifyAll``); the warnings come
from rospy's own threads, where the suite's warnings-as-errors would kill them."""
warnings.filterwarnings("ignore", category=DeprecationWarning, module="(rospy|rosgraph|genpy)")


ROS_LEAKS = ("ignore::ResourceWarning", "ignore::pytest.PytestUnraisableExceptionWarning")
"""rospy's xmlrpc clients leave sockets to the garbage collector (unclosed-socket
warnings, reported as unraisable); nothing of ours."""


def pytest_configure(config: pytest.Config) -> None:
    for line in (ROS_DEPRECATIONS, *ROS_LEAKS):
        config.addinivalue_line("filterwarnings", line)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def end_group(process: subprocess.Popen[bytes]) -> None:
    """SIGINT to the process group (roscore ends its children), then SIGKILL."""
    for sig, wait in ((signal.SIGINT, 15.0), (signal.SIGKILL, 5.0)):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            break
        try:
            process.wait(wait)
        except subprocess.TimeoutExpired:
            continue
    # children of roscore (rosmaster, rosout) share the group: make sure they are gone
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGKILL)


@pytest.fixture(scope="session")
def ros_master(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """`roscore` on 127.0.0.1:<free port>; this process's rospy client node on it."""
    port = free_port()
    uri = f"http://127.0.0.1:{port}/"
    home = tmp_path_factory.mktemp("ros-home")
    os.environ.update(ROS_MASTER_URI=uri, ROS_HOSTNAME="127.0.0.1", ROS_HOME=str(home))
    os.environ.pop("ROS_IP", None)
    log = (Path(home) / "roscore.log").open("wb")
    core = subprocess.Popen(
        ["roscore", "-p", str(port)], stdout=log, stderr=subprocess.STDOUT, start_new_session=True
    )
    try:
        master = rosgraph.Master("/melfa_test", master_uri=uri)
        deadline = time.monotonic() + START_TIMEOUT_S
        while not master.is_online():
            assert core.poll() is None, "roscore exited; see " + str(home / "roscore.log")
            assert time.monotonic() < deadline, "roscore did not come up"
            time.sleep(0.1)
        rospy.init_node("melfa_test", anonymous=True, disable_signals=True)
        yield uri
    finally:
        rospy.signal_shutdown("tests done")
        end_group(core)
        log.close()


@contextlib.contextmanager
def node_process(log_dir: Path, *args: str, name: str = "melfa") -> Iterator[Path]:
    """`python -m melfa ros --robot sim ARGS` as a subprocess, ready when its services are;
    yields its log file (the node's ROS log lines go to stdout)."""
    log_path = log_dir / f"{name}.log"
    log = log_path.open("wb")
    node = subprocess.Popen(
        [sys.executable, "-m", "melfa", "ros", "--robot", "sim", "--name", name, *args],
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    try:
        try:
            rospy.wait_for_service(f"/{name}/stop", timeout=START_TIMEOUT_S)
        except rospy.ROSException:
            pytest.fail("the node did not come up:\n" + log_path.read_text())
        yield log_path
    finally:
        end_group(node)
        log.close()
        deadline = time.monotonic() + 10  # the master forgets the node's services
        while time.monotonic() < deadline:
            try:
                rospy.wait_for_service(f"/{name}/stop", timeout=0.2)
            except rospy.ROSException:
                break
            time.sleep(0.1)


@pytest.fixture(scope="module")
def melfa_node(ros_master: str, tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """`python -m melfa ros --robot sim` for a whole module."""
    with node_process(tmp_path_factory.mktemp("node")):
        yield
