"""Real controller answers quoted in protocol.md, parsed; and written back by the same code."""

import pytest

from melfa.protocol import (
    JOINT_NAMES,
    POSE_NAMES,
    DState,
    ErrorLevel,
    ErrorStatus,
    OpenBanner,
    Position,
    PositionUnknown,
    RemoteProtocolError,
    ReplyReader,
    RunStatus,
    State,
    Status,
    StopStatus,
)
from melfa.protocol.messages import Ok

S10_PPOSF = "X;522.13;Y;288.62;Z;215.49;A;178.59;B;-13.61;C;1.90;;7,0;100;0.00;00000000"
S10_PPOSF_FL2 = "X;176.01;Y;33.14;Z;541.62;A;77.92;B;-25.59;C;106.80;;6,15728640;100;0.00;00000000"
S20_JPOSF = "J1;10.90;J2;70.76;J3;64.16;J4;-160.00;J5;40.06;J6;-183.40;;****,****;20;30.28;00000000"
S10_OPEN = (
    "3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-3SB;CRn-5xx;MELFA;05-07-14;Ver.K4a;ENG;(C);1;1;8;"
)
S1_STATE = "2.MB5;100;100;5;A1124220;1;1;;;;;;;;;REP;START;1;0"


def test_pposf_trace_s10() -> None:
    p = Position.parse(S10_PPOSF)
    assert p.values(*POSE_NAMES) == (522.13, 288.62, 215.49, 178.59, -13.61, 1.90)
    assert (p.fl1, p.fl2, p.override, p.speed, p.limits) == (7, 0, 100, 0.0, 0)


def test_pposf_multi_rotation_flag() -> None:
    assert Position.parse(S10_PPOSF_FL2).fl2 == 0x00F00000


def test_jposf_trace_s20_while_moving() -> None:
    p = Position.parse(S20_JPOSF)
    assert p.values(*JOINT_NAMES) == (10.90, 70.76, 64.16, -160.00, 40.06, -183.40)
    assert (p.fl1, p.fl2, p.override, p.speed) == (None, None, 20, 30.28)


def test_position_tolerates_missing_axis_extra_axes_and_crlf() -> None:
    p = Position.parse(
        "J1;1.00;J2;2.00;J3;3.00;J4;****;J5;5.00;J6;6.00;J7;7.50;J8;0.00;;****,****;100;0.00;00000000\r\n"
    )
    assert p["J4"] is None
    assert p["J7"] == 7.5
    assert p.names[-1] == "J8"
    with pytest.raises(PositionUnknown, match=r"position unknown .* J4 shows"):
        p.values("J4")
    assert not p.unknown
    with pytest.raises(RemoteProtocolError, match="no axis L1"):
        p.values("L1")


def test_position_with_l1() -> None:
    p = Position.parse("X;1;Y;2;Z;3;A;4;B;5;C;6;L1;0.00;;7,0;100;0.00;00000000")
    assert p["L1"] == 0.0


@pytest.mark.parametrize("answer", [S10_PPOSF, S10_PPOSF_FL2, S20_JPOSF])
def test_position_round_trip(answer: str) -> None:
    assert Position.parse(answer).to_answer() == answer


@pytest.mark.parametrize(
    "answer", ["", ";;7,0", "X;1.0;Y", "X;abc;;7,0", "X;1;;7;100", "x;1;;7,0", "X;nan;;7,0"]
)
def test_position_garbage(answer: str) -> None:
    with pytest.raises(RemoteProtocolError):
        Position.parse(answer)


def test_open_banner_trace_s10() -> None:
    b = OpenBanner.parse(S10_OPEN)
    assert (b.xyz_axes, b.joint_axes, b.program_extension, b.robot_type) == (
        63,
        63,
        "MB4",
        "RV-3SB",
    )
    assert (b.controller, b.version, b.language, b.task_max, b.edit_slot) == (
        "CRn-5xx",
        "Ver.K4a",
        "ENG",
        8,
        9,
    )
    assert b.to_answer() == S10_OPEN


def test_open_banner_default_layout_reads_back() -> None:
    b = OpenBanner(63, 63, "MB4", "RV-6S", "CRn-5xx", "24-01-01", "Ver.SIM", "ENG", 8)
    again = OpenBanner.parse(b.to_answer())
    assert (again.robot_type, again.task_max, again.edit_slot) == ("RV-6S", 8, 9)


def test_open_banner_too_short() -> None:
    with pytest.raises(RemoteProtocolError, match="fields"):
        OpenBanner.parse("3F;3F;7,0")


def test_state_example_s1() -> None:
    s = State.parse(S1_STATE)
    assert (s.program, s.line, s.override, s.edit_status) == ("2.MB5", 100, 100, "5")
    assert s.status == Status(
        RunStatus.OPERATION_ENABLED | RunStatus.SERVO_ON | RunStatus.REPEAT,
        StopStatus.PROGRAM_SELECT | StopStatus.STOP,
        4220,
    )
    assert (s.mode, s.start_condition, s.priority, s.mechanism_number) == ("REP", "START", 1, 0)
    assert s.to_answer() == S1_STATE


def test_state_through_the_reader_with_alarm() -> None:
    reader = ReplyReader()
    reader.feed(b"Qok" + S1_STATE.encode() + b"\r\n")
    reply = reader.next_reply()
    assert isinstance(reply, Ok) and reply.alarm
    assert State.parse(reply.answer).status.error == 4220


def test_dstate_example() -> None:
    d = DState.parse("09060;17;1")
    assert d.status.run == RunStatus.REPEAT | RunStatus.TEACH
    assert d.status.stop == StopStatus.WAIT | StopStatus.STOP
    assert (d.status.error, d.step, d.mechanism) == (0, 17, 1)
    assert d.to_answer() == "09060;17;1"


def test_running_and_servo_bits() -> None:
    d = DState.parse("E0000;1;1")
    assert RunStatus.RUNNING in d.status.run
    assert RunStatus.SERVO_ON in d.status.run


@pytest.mark.parametrize("field", ["", "A1", "ZZ000", "A112x", "A11242201"])
def test_status_garbage(field: str) -> None:
    with pytest.raises(RemoteProtocolError):
        Status.parse(field)


def test_error_answers() -> None:
    assert ErrorStatus.parse("") is None
    e = ErrorStatus.parse("4140;2")
    assert e == ErrorStatus(4140, ErrorLevel.LOW)
    assert e is not None and e.level is not None and e.level.letter == "L"
    assert e.to_answer() == "4140;2"
    with pytest.raises(RemoteProtocolError):
        ErrorStatus.parse("4140;7")
