"""`melfa doctor` against replay variants of real answers: it reports, it never dies.

Each variant is a real controller's answer changed the way firmware and lines vary it
(`tests.robot.relay.FaultRelay` swaps one reply on a real pty at 9600 8E2). Every run must
end with the report printed and written to its file (the byte trace beside it), the raw odd
reply quoted, and the exit code its verdict gives: 0 usable, 1 something blocks use.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.sim import KeySwitch, SimConfig, VirtualController
from tests.robot.relay import Fault, FaultRelay

runner = CliRunner()
ORIGIN_LOST_STATE = b"Qok;0;100;0;21125150;0;1;;;;;;;;;REP;START;1;0\r"  # [TRACE K9b-C1]


@pytest.fixture(autouse=True)
def profile(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    path = tmp_path / "profile.json"
    monkeypatch.setenv("MELFA_PROFILE", str(path))
    return path


@pytest.fixture
def relay() -> Iterator[FaultRelay]:
    relay = FaultRelay(VirtualController(SimConfig(strict=False)))
    yield relay
    relay.close()


def _doctor(relay: FaultRelay, tmp_path: Path) -> tuple[int, str, str]:
    report = tmp_path / "doctor.txt"
    result = runner.invoke(
        app,
        ["doctor", "--robot", relay.new_port(), "--timeout", "1", "--report", str(report)],
    )
    assert "Traceback" not in result.output, result.output
    assert report.exists(), result.output
    assert (tmp_path / "doctor.trace").read_text(encoding="utf-8"), "no trace beside the report"
    return result.exit_code, result.output, report.read_text(encoding="utf-8")


# (name, request to change, its reply instead, what the report must quote or say)
ODD_ANSWERS = [
    ("empty PAR answer", "PARCBAU232", b"QoK\r", "CBAU232"),
    ("PAR value without its name", "PARCBAU232", b"QoK9600\r", "QoK9600"),
    ("PAR refused", "PARCTERM232", b"QeR601000000\r", "QeR601000000"),
    ("ERRORRD 0;0 form", "ERRORRD", b"QoK0;0\r", "QoK0;0"),
    ("ERRORRD with 7 fields", "ERRORRD", b"QoK22-08-24;11:28:22;5150;The origin;2;;0\r", "5150"),
    ("ERRORRD garbled level", "ERRORRD", b"QoK22-08-24;11:28:22;5150;x;9;;0;515000100\r", "x;9"),
    ("PDIR odd", "PDIR", b"QoKTEST.MB4;9x4;23-02-01\r", "PDIR"),
    ("PRTVER refused", "PRTVERLISTL", b"QeR601000000\r", "QeR601000000"),
    ("empty CTERM", "PARCTERM232", b"QoK\r", "CTERM232"),
    ("Qok PAR", "PARCPRTY232", b"QokCPRTY232;2;1\r", "CPRTY232"),
]


@pytest.mark.parametrize(("name", "match", "payload", "quoted"), ODD_ANSWERS)
def test_an_odd_answer_is_reported_and_the_doctor_goes_on(
    relay: FaultRelay, tmp_path: Path, name: str, match: str, payload: bytes, quoted: str
) -> None:
    relay.add(Fault.replace(match, payload))
    code, output, report = _doctor(relay, tmp_path)
    assert quoted in report, (name, report)
    # The doctor went on to the end: the last probe is in the report.
    assert "CPRC232" in report and "verdict:" in report, (name, report)
    assert code in (0, 1), (name, output)


# Odd answers that make the robot unusable or that a resync cannot get past: exit 1.
BLOCKING = [
    ("empty PARRLNG answer", "PARRLNG", b"QoK\r", "RLNG"),
    ("PARRLNG refused", "PARRLNG", b"QeR601000000\r", "QeR601000000"),
    ("empty STATE answer", "STATE", b"QoK\r", "state"),
    ("STATE garbled", "STATE", b"QoK;0;100;0;ZZ\r", "ZZ"),
    ("origin lost in STATE", "STATE", ORIGIN_LOST_STATE, "origin"),
    (
        "origin lost in JPOSF",
        "JPOSF",
        b"QoKJ1;****;J2;****;J3;****;J4;****;J5;****;J6;****;;****,****;100;0.00;00000000\r",
        "****",
    ),
]


@pytest.mark.parametrize(("name", "match", "payload", "quoted"), BLOCKING)
def test_an_answer_that_blocks_use_is_reported_with_exit_1(
    relay: FaultRelay, tmp_path: Path, name: str, match: str, payload: bytes, quoted: str
) -> None:
    relay.add(Fault.replace(match, payload))
    code, output, report = _doctor(relay, tmp_path)
    assert quoted in report, (name, report)
    assert code == 1, (name, output)
    assert "BLOCKS USE" in report, (name, report)


def test_stop_refused_in_both_forms_blocks_use(relay: FaultRelay, tmp_path: Path) -> None:
    refusal = b"QeR601000000\r"
    relay.add(Fault.replace(";STOP", refusal), Fault.replace(";STOP", refusal))
    code, _output, report = _doctor(relay, tmp_path)
    assert code == 1
    assert "STOP cannot be relied on" in report


def test_a_lost_answer_is_reported_and_the_doctor_resynchronises(
    relay: FaultRelay, tmp_path: Path
) -> None:
    relay.add(Fault.drop("PARCSTOP232"))
    code, _output, report = _doctor(relay, tmp_path)
    assert "no answer" in report and "CPRC232" in report
    assert code == 0, report


@pytest.mark.parametrize(
    ("key", "what"), [(KeySwitch.AUTO_OP, "AUTO (Op.)"), (KeySwitch.TEACH, "TEACH")]
)
def test_the_key_outside_auto_ext_blocks_use(tmp_path: Path, key: KeySwitch, what: str) -> None:
    relay = FaultRelay(VirtualController(SimConfig(key=key, strict=False)))
    try:
        code, _output, report = _doctor(relay, tmp_path)
    finally:
        relay.close()
    assert code == 1
    assert what in report and "BLOCKS USE" in report


def test_origin_lost_on_the_simulator_blocks_use(tmp_path: Path) -> None:
    relay = FaultRelay(VirtualController(SimConfig(origin_set=False)))
    try:
        code, _output, report = _doctor(relay, tmp_path)
    finally:
        relay.close()
    assert code == 1
    assert "origin" in report and "****" in report


def test_a_clean_controller_is_usable(relay: FaultRelay, tmp_path: Path) -> None:
    code, output, report = _doctor(relay, tmp_path)
    assert code == 0, output
    assert report.rstrip().endswith("verdict: usable")
