"""The virtual controller's answers, byte for byte, and its refusals with the real numbers."""

from __future__ import annotations

import pytest

from melfa.protocol.answers import Position, State
from melfa.protocol.messages import EditRefused, Ok, Refused
from melfa.sim import SimConfig, VirtualController
from tests.fixtures_sim import Driver

BANNER = (
    b"QoK3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-6S;CRn-5xx;MELFA;05-07-14;Ver.K4a;ENG;"
    b"MELFA VIRTUAL CONTROLLER (SIMULATED CR2B-574);1;1;8;\r"
)


# ----------------------------------------------------------------------- session, rights


def test_everything_before_open_is_illegal_where_open_is_required() -> None:
    drive = Driver(VirtualController(SimConfig(open_required=True)))
    for command in ("STATE", "CNTLON", "JPOSF", "EXECMOV P1", "CLOSE"):
        assert drive.send(command) == b"QeR601000000\r"


def test_open_answers_the_banner(drive: Driver) -> None:
    assert drive.send("OPEN=NARCUSR") == BANNER


def test_unknown_command_is_illegal(drive: Driver) -> None:
    drive.ok("OPEN=X")
    assert drive.send("FROBNICATE") == b"QeR601000000\r"
    assert drive.send("STATEX") == b"QeR601000000\r"


def test_close_ends_the_session_and_drops_rights() -> None:
    drive = Driver(VirtualController(SimConfig(open_required=True)))
    drive.ok("OPEN=X")
    drive.ok("CNTLON")
    assert drive.send("CLOSE") == b"QoK\r"
    assert drive.send("STATE") == b"QeR601000000\r"
    drive.ok("OPEN=X")
    assert drive.send("SRVON") == b"QeR602000000\r"


@pytest.mark.parametrize(
    "command",
    [
        "SRVON",
        "EXECOVRD 10",
        "OVRD=50",
        "RUN1;1",
        "JOG00;00;00;01;00",
        "PRGLOAD=COSIROP",
        "RSTALRM",
    ],
)
def test_rights_are_needed(drive: Driver, command: str) -> None:
    drive.ok("OPEN=X")
    assert drive.send(command) == b"QeR602000000\r"


@pytest.mark.parametrize("command", ["SRVOFF", "STOP", "STATE", "JPOSF", "HNDSTS", "SAVE"])
def test_rights_are_not_needed(drive: Driver, command: str) -> None:
    drive.ok("OPEN=X")
    assert drive.send(command).startswith(b"QoK")


def test_rights_for_slot_reset_is_configurable() -> None:
    drive = Driver(VirtualController(SimConfig(rights_for_slot_reset=True)))
    drive.ok("OPEN=X")
    assert drive.send("SLOTINIT") == b"QeR602000000\r"
    drive.ok("CNTLON")
    assert drive.send("SLOTINIT") == b"QoK\r"


# ------------------------------------------------------------------------ state, servo


def test_state_idle_like_the_trace(drive: Driver) -> None:
    sim = VirtualController(programs={})
    drive = Driver(sim)
    drive.ok("OPEN=X")
    # [TRACE S21] `QoK;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0`
    assert drive.send("STATE") == b"QoK;0;100;0;01120;0;1;;;;;;;;;REP;START;1;0\r"
    assert drive.send("DSTATE") == b"QoK01120;0;1\r"


def test_state_bits_follow_rights_and_servo(drive: Driver) -> None:
    drive.ok("OPEN=X")
    drive.ok("CNTLON")
    drive.ok("SRVON")
    drive.ok("PRGLOAD=COSIROP")
    state = State.parse(drive.ok("STATE"))
    assert state.program == "COSIROP.MB4"
    assert state.status.to_field() == "A1120"  # enabled, servo on, repeat; STOP + select
    drive.ok("SRVOFF")
    drive.ok("CNTLOFF")
    assert State.parse(drive.ok("STATE")).status.to_field() == "01120"


def test_jposf_and_pposf_formats(ready: Driver) -> None:
    assert ready.send("JPOSF") == (
        b"QoKJ1;0.00;J2;0.00;J3;90.00;J4;0.00;J5;90.00;J6;0.00;;****,****;100;0.00;00000000\r"
    )
    assert ready.send("PPOSF") == (
        b"QoKX;400.00;Y;0.00;Z;645.00;A;180.00;B;0.00;C;180.00;;7,0;100;0.00;00000000\r"
    )


def test_override(ready: Driver) -> None:
    assert ready.send("OVRD=50") == b"QoK50\r"
    assert ready.send("OVRD") == b"QoK50\r"
    assert Position.parse(ready.ok("JPOSF")).override == 50
    assert ready.send("OVRD=0").startswith(b"QeR")
    assert ready.send("OVRD=101").startswith(b"QeR")
    assert ready.send("OVRD") == b"QoK50\r"


def test_hand(ready: Driver) -> None:
    ready.ok("HNDOFF1")
    ready.ok("HNDON2")
    assert ready.send("HNDSTS").startswith(b"QoK900;2;1;902;1;1;904;")
    assert ready.send("HNDON9").startswith(b"QeR")
    ready.ok("EXECHOPEN 1")
    assert ready.send("HNDSTS").startswith(b"QoK900;1;1;")


def test_parameters_like_the_traces(drive: Driver) -> None:
    drive.ok("OPEN=X")
    assert drive.send("PARRLNG") == b"QoKRLNG;1;1\r"
    assert drive.send("PARMEXTL") == b"QoKMEXTL;0.00, 0.00, 0.00, 0.00, 0.00, 0.00;6\r"
    mejar = drive.ok("PARMEJAR").split(";")
    assert mejar[0] == "MEJAR" and mejar[2] == "16"
    assert mejar[1].split(", ")[:4] == ["-170.00", "170.00", "-92.00", "135.00"]
    assert drive.send("KEYWDptest") == b"QoK\r"
    for which in ("LISTL", "EMDAT", "VALS"):
        assert drive.send(f"PRTVER{which}") == b"QoK1\r"


# ------------------------------------------------------------------------------ EXEC


def test_exec_replies_on_accept_and_refuses_while_moving(ready: Driver) -> None:
    ready.ok("EXECJ1=(90,0,90,0,90,0)")
    ready.ok("EXECMOV J1")
    # 90° of J1 at 401 °/s: about 0.22 s. EXECREM while moving is the S6 busy test.
    assert ready.send("EXECREM Waiting...") == b"QeR564000000\r"
    assert ready.send("EXECMOV J1") == b"QeR564000000\r"
    assert State.parse(ready.ok("STATE")).status.run & 0x40
    ready.wait(0.1)
    j1 = Position.parse(ready.ok("JPOSF"))["J1"]
    assert j1 is not None and 0 < j1 < 90
    ready.wait(1.0)
    assert ready.send("EXECREM Waiting...") == b"QoK\r"
    assert Position.parse(ready.ok("JPOSF"))["J1"] == 90.0


def test_exec_relative_moves(ready: Driver) -> None:
    # At home the tool Z axis points down, so -50 along tool Z is 50 mm up in the world.
    ready.ok("EXECMOV P_CURR*(0,0,-50,0,0,0)")
    ready.wait(2)
    z_after_tool_move = Position.parse(ready.ok("PPOSF"))["Z"]
    assert z_after_tool_move == pytest.approx(695.0, abs=0.01)
    ready.ok("EXECJSTEP=(10,0,0,0,0,0)")  # S18's joint jog: MOV J_CURR + JSYM3
    ready.ok("EXECMOV J_CURR+JSTEP")
    ready.wait(2)
    assert Position.parse(ready.ok("JPOSF"))["J1"] == pytest.approx(10.0)


def test_stop_halts_an_exec_motion(ready: Driver) -> None:
    ready.ok("EXECJSTEP=(100,0,0,0,0,0)")
    ready.ok("EXECMOV J_CURR+JSTEP")
    ready.wait(0.1)
    assert ready.send("STOP", slot=0) == b"QoK\r"
    ready.wait(0.5)  # the arm decelerates along its path
    stopped = Position.parse(ready.ok("JPOSF"))["J1"]
    ready.wait(2)
    assert Position.parse(ready.ok("JPOSF"))["J1"] == stopped
    assert stopped is not None and 0 < stopped < 100
    assert ready.send("EXECREM Waiting...") == b"QoK\r"


def test_exec_with_servo_off_raises_an_alarm(drive: Driver) -> None:
    drive.ok("OPEN=X")
    drive.ok("CNTLON")
    drive.ok("EXECJ1=(10,0,90,0,90,0)")
    assert drive.send("EXECMOV J1") == b"Qer200000000\r"
    assert drive.send("STATE").startswith(b"Qok")


def test_joint_limit_raises_an_alarm_until_rstalrm(ready: Driver) -> None:
    ready.ok("EXECJ1=(175,0,90,0,90,0)")
    assert ready.send("EXECMOV J1") == b"Qer216000000\r"
    assert ready.send("ERROR") == b"Qok2160;1\r"  # H level
    assert ready.send("JPOSF").startswith(b"QokJ1;0.00;")
    assert ready.send("EXECREM x") == b"Qer560000000\r"
    state = State.parse(ready.send("STATE")[3:-1].decode())
    assert state.status.error == 2160
    assert not state.status.run & 0x20  # an H-level error switches the servo off
    assert ready.send("RSTALRM") == b"QoK\r"
    assert ready.send("ERROR") == b"QoK\r"
    assert ready.send("ERRORMES2160") == b"QoKJoint angle exceeds the limit\r"
    assert ready.send("ERRORLOGTOP").startswith(b"QoK24-01-01;00:00:00;2160;")


def test_rstalrm_needs_rights(ready: Driver) -> None:
    ready.ok("EXECJ1=(175,0,90,0,90,0)")
    assert ready.send("EXECMOV J1") == b"Qer216000000\r"
    assert ready.send("CNTLOFF") == b"Qok\r"
    assert ready.send("RSTALRM") == b"Qer602000000\r"


def test_exec_needs_program_is_configurable() -> None:
    drive = Driver(VirtualController(SimConfig(exec_needs_program=True)))
    drive.ok("OPEN=X")
    drive.ok("CNTLON")
    assert drive.send("EXECOVRD 10") == b"QeR414000000\r"
    drive.ok("PRGLOAD=COSIROP")
    assert drive.send("EXECOVRD 10") == b"QoK\r"


# ------------------------------------------------------------------------------- JOG


def test_jog_moves_while_renewed_and_stops_by_itself(ready: Driver) -> None:
    ready.ok("JOG00;00;00;01;00")  # J1 +
    for _ in range(10):
        ready.wait(0.1)
        ready.ok("JOG00;00;00;01;00")
    moving = Position.parse(ready.ok("JPOSF"))["J1"]
    assert moving is not None and moving > 0
    ready.wait(0.5)  # no JOG for longer than the ~140 ms watchdog
    stopped = Position.parse(ready.ok("JPOSF"))["J1"]
    ready.wait(1.0)
    assert Position.parse(ready.ok("JPOSF"))["J1"] == stopped
    # it stopped at the watchdog deadline, not when we looked
    per_second = moving / 1.0
    assert stopped == pytest.approx(moving + per_second * 0.14, abs=0.02)


def test_a_longer_watchdog_is_the_arms_and_the_controllers() -> None:
    """`SimConfig.jog_watchdog_s` is one setting: the simulated arm keeps jogging exactly as
    long as the controller says it is jogging, and both stop at its deadline."""
    drive = Driver(VirtualController(SimConfig(jog_watchdog_s=0.5)))
    for command in ("OPEN=TEST", "CNTLON", "SRVON", "JOG00;00;00;01;00"):
        drive.ok(command)
    drive.wait(0.1)
    at_renewal = Position.parse(drive.ok("JPOSF"))["J1"]
    drive.ok("JOG00;00;00;01;00")  # renewed at t = 0.1: the deadline is 0.6
    drive.wait(0.3)  # past the controller's usual 140 ms, within this one's 500 ms
    still = Position.parse(drive.ok("JPOSF"))["J1"]
    assert drive.controller.jogging is not None and drive.controller.arm.is_moving
    assert at_renewal is not None and still is not None and still > at_renewal
    drive.wait(0.5)
    stopped = Position.parse(drive.ok("JPOSF"))["J1"]
    assert drive.controller.jogging is None and not drive.controller.arm.is_moving
    per_second = at_renewal / 0.1
    assert stopped == pytest.approx(at_renewal + per_second * 0.5, abs=0.02)


def test_jog_minus_mask_comes_first(ready: Driver) -> None:
    ready.ok("JOG00;00;01;00;00")
    ready.wait(0.1)
    j1 = Position.parse(ready.ok("JPOSF"))["J1"]
    assert j1 is not None and j1 < 0


def test_jog_zero_masks_stop_at_once(ready: Driver) -> None:
    ready.ok("JOG00;00;00;01;00")
    ready.wait(0.1)
    ready.ok("JOG00;00;00;00;00")
    here = Position.parse(ready.ok("JPOSF"))["J1"]
    ready.wait(0.1)
    assert Position.parse(ready.ok("JPOSF"))["J1"] == here


def test_jog_refusals(drive: Driver) -> None:
    drive.ok("OPEN=X")
    drive.ok("CNTLON")
    assert drive.send("JOG00;00;00;01;00") == b"QeR200000000\r"
    drive.ok("SRVON")
    assert drive.send("JOG00;00;00") == b"QeR601000000\r"
    unsupported = Driver(VirtualController(SimConfig(jog_supported=False)))
    unsupported.ok("OPEN=X")
    unsupported.ok("CNTLON")
    unsupported.ok("SRVON")
    assert unsupported.send("JOG00;00;00;01;00") == b"QeR203000000\r"


# --------------------------------------------------------------------------- editing


def _upload(drive: Driver, name: str, *items: str) -> bytes:
    drive.ok("NEW")
    drive.ok(f"LOAD={name}")
    for item in items:
        reply = drive.send("EMDAT" + item, robot=1, slot=9)
        if not reply.startswith(b"QoK"):
            return reply
    return drive.send("SAVE")


def test_upload_list_and_directory(drive: Driver) -> None:
    drive.ok("OPEN=X")
    assert (
        _upload(drive, "1", "10 MOV P1\x0b20 HOPEN 1\x0b30 END", "P1=(400,0,600,180,0,180)(7,0)")
        == b"QoK\r"
    )
    drive.ok("LOAD=1")
    assert drive.send("LISTL<", slot=9) == b"QoK10 MOV P1\x0b20 HOPEN 1\x0b30 END;3;0\r"
    assert drive.send("LISTITOP", slot=9) == b"QoK10 MOV P1\r"
    assert drive.send("LISTI+1", slot=9) == b"QoK20 HOPEN 1\r"
    assert drive.send("LISTPTOP", slot=9) == (
        b"QoKP1=(+400.00,+0.00,+600.00,+180.00,+0.00,+180.00)(7,0)\r"
    )
    drive.ok("NEW")
    assert drive.send("FCHECK1") == b"QoKN\r"
    assert drive.send("FCHECKNOPE") == b"QoKF\r"
    first = drive.ok("PDIR<").split(";")
    assert first[0] == "COSIROP.MB4" and first[3] == "2"
    entry = drive.ok("PDIR02").split(";")
    assert entry[0] == "1.MB4" and entry[5:7] == ["3", "1"]


def test_bare_line_numbers_delete_lines(drive: Driver) -> None:
    drive.ok("OPEN=X")
    _upload(drive, "A", "10 MOV P1\x0b20 END")
    assert _upload(drive, "A", "10\x0b20", "10 HOPEN 1") == b"QoK\r"
    drive.ok("LOAD=A")
    assert drive.send("LISTL<", slot=9) == b"QoK10 HOPEN 1;1;0\r"


def test_emdat_refuses_a_bad_line_with_its_index_and_column(drive: Driver) -> None:
    drive.ok("OPEN=X")
    drive.ok("LOAD=B")
    assert drive.reply("EMDAT10 MOV P1\x0b20 MOV (\x0b30 END", slot=9) == EditRefused(
        4220, 2, 8, alarm=True, detail="00000"
    )
    assert drive.send("EMDAT10 MOV P1\x0b20 MOV (", slot=9) == b"Qer422000000;2;8\r"
    assert drive.send("EMDAT40000 END", slot=9) == b"Qer442000000;1;1\r"
    # nothing of a refused batch was taken
    assert drive.send("LISTL<", slot=9) == b"QoK;0;0\r"


def test_save_of_a_broken_program_is_refused_and_keeps_the_old_one() -> None:
    drive = Driver(VirtualController(SimConfig(check_syntax_on_emdat=False)))
    drive.ok("OPEN=X")
    assert _upload(drive, "P", "10 MOV P1\x0b20 END") == b"QoK\r"
    assert _upload(drive, "P", "10\x0b20", "10 MOV (\x0b20 END") == b"QeR422000000\r"
    drive.ok("NEW")
    drive.ok("LOAD=P")
    assert drive.send("LISTL<", slot=9) == b"QoK10 MOV P1\x0b20 END;2;0\r"


def test_emdat_without_load_is_refused(drive: Driver) -> None:
    drive.ok("OPEN=X")
    assert drive.send("EMDAT10 END", slot=9).startswith(b"QeR")


def test_fdel(drive: Driver) -> None:
    drive.ok("OPEN=X")
    _upload(drive, "GONE", "10 END")
    drive.ok("FDELGONE")
    assert drive.send("FCHECKGONE") == b"QoKF\r"
    assert drive.send("FDELGONE") == b"QeR414000000\r"


# --------------------------------------------------------------------------- running


def test_run_stop_resume(ready: Driver) -> None:
    _upload(ready, "R", "10 DLY 0.5\x0b20 DLY 0.5\x0b30 END")
    ready.ok("RUNR;1")
    state = State.parse(ready.ok("STATE"))
    assert state.program == "R.MB4" and state.status.run & 0x40
    assert ready.send("RUNR;1") == b"QeR418000000\r"
    assert ready.send("FDELR") == b"QeR418000000\r"
    assert ready.send("EXECOVRD 5") == b"QeR564000000\r"
    ready.ok("STOP")
    paused = State.parse(ready.ok("STATE"))
    assert not paused.status.run & 0x40 and paused.status.stop == 0x06  # [TRACE K9b-RAW]
    ready.ok("RUNR;1")
    assert State.parse(ready.ok("STATE")).status.run & 0x40
    ready.wait(10)
    assert not State.parse(ready.ok("STATE")).status.run & 0x40


def test_run_of_a_missing_program(ready: Driver) -> None:
    assert ready.send("RUNNOPE;1") == b"QeR414000000\r"


def test_garbage_gets_a_clean_refusal(drive: Driver) -> None:
    drive.ok("OPEN=X")
    sim = drive.controller
    assert sim.handle(b"\xff\xfe\x00garbage\r", 0.0) == b"QeR601000000\r"
    assert sim.handle(b"1;1;" + b"EXECREM " + b"x" * 300 + b"\r", 0.0) == b"QeR608000000\r"
    assert sim.handle(b"", 0.0) == b"QeR601000000\r"
    assert drive.send("STATE").startswith(b"QoK")


def test_too_long_error_is_configurable() -> None:
    sim = VirtualController(SimConfig(too_long_error=3270))
    assert sim.handle(b"1;1;" + b"x" * 300, 0.0) == b"QeR327000000\r"


def test_replies_are_typed_the_same_way(drive: Driver) -> None:
    assert drive.reply("FROBNICATE") == Refused(6010, detail="00000")
    assert isinstance(drive.controller.respond("1;1;OPEN=X", 0.0), Ok)


def test_run_moves_the_arm_and_reports_the_line(ready: Driver) -> None:
    _upload(
        ready,
        "M",
        "10 MOV J1\x0b20 DLY 0.5\x0b30 END",
        "J1=(45,0,90,0,90,0)",
    )
    ready.ok("RUNM;1")
    ready.wait(0.2)
    state = State.parse(ready.ok("STATE"))
    assert state.line == 10 and state.status.run & 0x40
    j1 = Position.parse(ready.ok("JPOSF"))["J1"]
    assert j1 is not None and 0 < j1 < 45
    ready.wait(5)
    assert Position.parse(ready.ok("JPOSF"))["J1"] == 45.0
    assert not State.parse(ready.ok("STATE")).status.run & 0x40


def test_a_program_error_becomes_an_alarm(ready: Driver) -> None:
    _upload(ready, "BAD", "10 MOV J1\x0b20 END", "J1=(175,0,90,0,90,0)")
    # RUN is accepted; the first step fails at once, so the reply already shows the alarm
    assert ready.send("RUNBAD;1") == b"Qok\r"
    ready.wait(0.1)
    assert ready.send("ERROR") == b"Qok2160;1\r"
    state = State.parse(ready.send("STATE")[3:-1].decode())
    assert state.status.error == 2160 and not state.status.run & 0x40
    assert ready.send("ERRORLOGTOP").split(b";")[2:7] == [
        b"2160",
        b"Joint angle exceeds the limit",
        b"1",
        b"BAD",
        b"10",
    ]
