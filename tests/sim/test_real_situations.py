"""Situations of the real controller the simulator reproduces: the MODE key, a lost origin,
a program stopped mid-way, the stop-status bits, strict mode, the 4- and 9-digit forms.

Expected bytes come from the recordings in tests/fixtures/real_traffic.py [TRACE] where
there are any; the rest is the simulator's documented choice (docs/simulator.md).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from melfa.protocol import ErrorLogEntry, Ok, Parameter, Position, State
from melfa.protocol.answers import RunStatus, StopStatus
from melfa.protocol.commands import COMMANDS, Evidence
from melfa.sim import SUPPORTED_COMMANDS, SimConfig, VirtualController
from melfa.sim.config import KeySwitch
from melfa.sim.controller import strict_commands
from tests.fixtures_sim import Driver

SLOW = "10 SPD 20\n20 OVRD 10\n30 MVS P1\n40 END\nP1=(300,300,400,180,0,180)(7,0)\n"
"""A program that sets a crawling speed and moves for a long time."""
SHORT = "10 DLY 0.5\n20 DLY 0.5\n30 END\n"


def _ready(config: SimConfig | None = None, **programs: str) -> Driver:
    drive = Driver(VirtualController(config or SimConfig(), programs=programs or None))
    drive.ok("OPEN=TOOLBOX")
    drive.ok("CNTLON")
    return drive


def _state(drive: Driver) -> State:
    reply = drive.reply("STATE")
    assert isinstance(reply, Ok), reply
    return State.parse(reply.answer)


# ------------------------------------------------------------------------------ MODE key


@pytest.mark.parametrize("key", [KeySwitch.TEACH, KeySwitch.AUTO_OP])
def test_outside_auto_ext_cntlon_is_accepted_but_operation_is_refused(key: KeySwitch) -> None:
    drive = _ready(SimConfig(key=key), R=SHORT)
    # [TRACE K9b-PROG] CNTLON → QoK, then SLOTINIT → QeR602000000 "The Operation is disable".
    assert drive.send("SLOTINIT") == b"QeR602000000\r"
    assert drive.send("ERRORMES602000000") == b"QoKThe Operation is disable\r"
    for command in ("RUNR;1", "SRVON", "OVRD=50", "EXECMOV P1", "RSTPRG"):
        assert drive.send(command) == b"QeR602000000\r", command
    for command in ("STATE", "PPOSF", "PDIR<", "LOAD=R", "NEW", "ERRORRD<;0"):
        assert drive.send(command).startswith(b"QoK"), command


def test_teach_shows_in_the_status_bits_and_turning_the_key_takes_the_rights() -> None:
    drive = _ready(SimConfig(key=KeySwitch.TEACH))
    status = _state(drive).status
    # [TRACE K9b-PROG] `09920`: run 0x09 (repeat, teach), stop 0x92 (0x80 with TEACH).
    assert RunStatus.TEACH in status.run and StopStatus.TEACH_PENDANT in status.stop
    drive.controller.turn_key(KeySwitch.AUTO_EXT, drive.now)
    assert RunStatus.TEACH not in _state(drive).status.run
    assert drive.send("SRVON") == b"QeR602000000\r"  # the rights went with the key
    drive.ok("CNTLON")
    drive.ok("SRVON")
    drive.ok("SLOTINIT")


# ------------------------------------------------------------------------- lost origin


def test_a_lost_origin_shows_stars_and_refuses_motion_with_5150() -> None:
    drive = _ready(SimConfig(origin_set=False), R=SHORT)
    drive.ok("SRVON")
    pose = Position.parse(drive.ok("PPOSF"))
    joints = Position.parse(drive.ok("JPOSF"))
    assert pose.unknown and joints.unknown and pose.fl1 is None
    assert drive.ok("PPOSF").startswith("X;****;Y;****")
    # [TRACE K9b-C1] RUNPNO2;1 → Qer515000000, STATE `…;21125150;…`, ERRORRD's entry.
    assert drive.send("RUNR;1") == b"Qer515000000\r"
    assert drive.send("CNTLOFF") == b"Qok\r"
    state = _state(drive)
    assert state.status.error == 5150 and state.status.to_field() == "21125150"
    assert drive.send("ERRORMES515000000") == b"QokThe origin has not been set\r"
    entry = ErrorLogEntry.parse(drive.send("ERRORRD<;0").decode()[3:-1])
    assert entry is not None and entry.code.wire == "515000100" and entry.line == 0
    assert drive.send("ERRORRD+1;0") == b"Qok\r"
    assert drive.send("CNTLON") == b"Qok\r"
    assert drive.send("EXECMOV P1") == b"Qer515000000\r"
    assert drive.send("JOG00;00;00;01;00") == b"Qer515000000\r"


# ------------------------------------------------------------------- STOP and restart


def test_stop_pauses_at_the_line_and_only_slotinit_starts_over() -> None:
    drive = _ready(R=SHORT, OTHER=SHORT)
    drive.ok("SRVON")
    drive.ok("RUNR;1")
    drive.wait(0.7)
    drive.ok("STOP")
    paused = drive.ok("STATE").split(";")
    # [TRACE K9b-RAW] paused mid-program: edit status 4, stop bits 0x06, not running.
    assert paused[1] == "20" and paused[3] == "4" and paused[4][2:4] == "06"
    assert paused[-1] == "0" and paused[15] == "REP"
    assert drive.send("RUNOTHER;1") == b"QeR512000000\r"  # [TRACE K9b-RAW] not PSA
    drive.ok("SLOTINIT")
    idle = drive.ok("STATE").split(";")
    assert idle[3] == "0" and idle[4][2:4] == "12"
    drive.ok("RUNR;1")
    assert _state(drive).line == 10  # from the beginning, not from line 20


def test_a_paused_programs_speed_does_not_slow_what_runs_meanwhile() -> None:
    """Issue 17: after a STOP, step jogs crawled at the paused program's SPD 20 × OVRD 10."""
    drive = _ready(S=SLOW)
    drive.ok("SRVON")
    drive.ok("RUNS;1")
    drive.wait(0.5)
    drive.ok("STOP")
    drive.wait(1.0)
    start = Position.parse(drive.ok("PPOSF"))["Z"]
    drive.ok("EXECMVS P_CURR+(0,0,10,0,0,0)")
    drive.wait(1.0)
    moved = Position.parse(drive.ok("PPOSF"))["Z"]
    assert start is not None and moved is not None and moved - start > 9.9
    # The program gets its own settings back when it resumes: it crawls again.
    drive.ok("RUNS;1")
    drive.wait(0.5)
    before = Position.parse(drive.ok("PPOSF")).values("X", "Y")
    drive.wait(1.0)
    after = Position.parse(drive.ok("PPOSF")).values("X", "Y")
    assert 0 < max(abs(a - b) for a, b in zip(after, before, strict=True)) < 3.0


# ---------------------------------------------------------------- answers on record


def test_reads_rt_toolbox_and_the_thesis_send() -> None:
    drive = _ready()
    assert drive.send("PRTVERVALS") == b"QoK1\r"
    assert drive.send("JOGST", slot=0) == b"QoK\r"
    assert drive.send("KEYWDp991231") == b"QoK\r"
    assert Parameter.parse(drive.ok("PARRLNG")) == Parameter("RLNG", ("1",), 1)
    assert drive.ok("PNRLNG") == "LNG;ENG;1"
    assert drive.ok("PNRJOGJSP") == "JOGJSP;0.10, 0.01, 10.00;3"
    assert len(drive.ok("PTIME").split(";")) == 22
    assert drive.ok("TIME") == "24-01-0100:00:00"
    zeros = "X;0.00;Y;0.00;Z;0.00;A;0.00;B;0.00;C;0.00"
    assert drive.ok("GPPOSF") == zeros + ";;0,0;100;0.00;00000000"  # [TRACE K9b-PROG]
    assert drive.ok("GJPOSF").endswith(";;****,****;100;0.00;00000000")
    banner = drive.ok("OPEN=NARCUSR").split(";")
    assert banner[6:11] == ["RV-6S", "CRn-5xx", "MELFA", "05-07-14", "Ver.K4a"]


def test_slot_minus_one_reads_the_current_position() -> None:
    drive = _ready()
    reply = drive.controller.handle(b"1;-1;PPOSF\r", drive.now)
    assert reply.startswith(b"QoKX;") and Position.parse(reply[3:-1].decode())["X"] is not None


# ------------------------------------------------------------------- strict, digits


def test_strict_refuses_documented_only_commands_in_the_real_form() -> None:
    strict = _ready(SimConfig(strict=True))
    lenient = _ready(SimConfig(strict=False))
    for command in ("CALIB", "HNDSTS", "JOG00;00;00;01;00", "LISTP TOP", "FCHECK R"):
        assert strict.send(command) == b"QeR601000000\r", command
        assert lenient.send(command) != b"QeR601000000\r", command
    # [TRACE] RT ToolBox's slot forms are served; a slot form never seen is not.
    assert strict.send("JOGST", slot=0) == b"QoK\r"
    assert strict.send("STATE", slot=0) == b"QeR601000000\r"


def test_strict_serves_exactly_the_commands_with_real_evidence() -> None:
    served = strict_commands()
    assert {"OPEN=", "STATE", "PPOSF", "GJPOSF", "ERRORRD", "SLOTINIT", "EMDAT"} <= set(served)
    assert all(COMMANDS[name].evidence is not Evidence.DOC for name in served)
    assert "CALIB" not in served and "JOG" not in served


def test_edit_refusals_follow_the_digit_setting() -> None:
    for nine, expected in ((True, b"Qer422000000;1;8\r"), (False, b"Qer4220;1;8\r")):
        drive = _ready(SimConfig(nine_digit_errors=nine))
        drive.ok("LOAD=E")
        assert drive.send("EMDAT10 MOV (", slot=9) == expected


def test_the_documented_strict_list_is_the_served_list() -> None:
    doc = (Path(__file__).parents[2] / "docs" / "simulator.md").read_text(encoding="utf-8")
    served_part = doc.split("Served in strict mode", 1)[1].split("Refused in strict mode", 1)
    table = [line for line in served_part[0].splitlines() if line.startswith("| `")]
    listed = {name for line in table for name in re.findall(r"`([A-Z]+=?)`", line)}
    assert listed == set(strict_commands())
    refused = set(re.findall(r"`([A-Z]+=?)`", served_part[1].split("\n\n", 1)[0]))
    assert refused == set(SUPPORTED_COMMANDS) - set(strict_commands())
