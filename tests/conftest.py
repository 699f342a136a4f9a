"""Shared test settings."""

import os
import signal

import pytest
from hypothesis import HealthCheck, settings

# Property tests: modest and repeatable in CI (2 cores, shared), thorough on request.
settings.register_profile(
    "default",
    max_examples=100,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("ci", parent=settings.get_profile("default"), derandomize=True)
settings.register_profile("thorough", parent=settings.get_profile("default"), max_examples=2000)
_default_profile = "ci" if os.environ.get("CI") else "default"
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", _default_profile))

# Every simulator in the suite is strict (refuses what no real controller was seen to answer)
# and answers refusals in the real 9-digit form, unless a test says otherwise; the
# simulator's own tests of documented-only commands opt out in tests/sim/conftest.py.
os.environ.setdefault("MELFA_SIM_STRICT", "1")

# A robot profile (`melfa doctor`) of the developer's own must never change what tests see.
if "MELFA_PROFILE" not in os.environ:
    import tempfile
    from pathlib import Path

    os.environ["MELFA_PROFILE"] = str(Path(tempfile.mkdtemp(prefix="melfa-test-")) / "p.json")

# Tests press Ctrl-C (SIGINT) on the commands they start. A suite started in the background
# (`scripts/test &` from a script, nohup) inherits SIGINT ignored, and every command it
# starts would too and never see the key: the suite takes Python's usual handler, which the
# commands it starts inherit as the default.
signal.signal(signal.SIGINT, signal.default_int_handler)

# roslibpy's rosapi helpers (`get_services`, `get_topics`, …) wait 3 s for an answer: short
# for a loaded 2-core CI machine (a clean clone under a second suite saw `get_services` time
# out). A hang guard, set through roslibpy's own setting.
try:
    import roslibpy
except ImportError:  # the ROS 1 tests under Debian's python3 have no roslibpy
    pass
else:
    roslibpy.set_rosapi_timeout(30)

# Shared simulator fixtures: a fresh pty (or TCP port) per test, served by the virtual controller.
from tests.fixtures_sim import not_strict, sim_pty_path, sim_tcp_url  # noqa: E402, F401


def pytest_addoption(parser: pytest.Parser) -> None:
    """`--robot URL` reruns tests/robot against real hardware instead of the simulator."""
    parser.addoption(
        "--robot",
        action="store",
        default=None,
        help="run tests/robot against this robot (device path, tcp://, pyserial URL); "
        "default: the simulator over a pty (also settable with $MELFA_TEST_ROBOT)",
    )
