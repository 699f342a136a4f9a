"""`melfa ros` where rospy does not import: a clear way forward, never a traceback."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.cli.ros_commands import REEXEC_ENV
from melfa.ros.node import ros_available

pytestmark = pytest.mark.skipif(ros_available(), reason="rospy imports here: the node would run")


def test_without_rospy_it_says_how_to_run_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(REEXEC_ENV, "1")  # as if already re-executed: no second try
    result = CliRunner().invoke(app, ["ros", "--robot", "sim"])
    assert result.exit_code == 2
    assert "scripts/ros-env melfa ros --robot sim" in " ".join(result.output.split())
    assert "Traceback" not in result.output


def test_a_bad_rate_is_a_usage_error() -> None:
    result = CliRunner().invoke(app, ["ros", "--max-rate", "0"])
    assert result.exit_code == 2 and "--max-rate must be positive" in result.output
