"""Minimal reproductions of what real MELFA programs showed the checker (issue 25).

Each test is the smallest program that showed a false alarm, a missed mistake or a wrong
reading of MELFA BASIC V; the reference each rule follows is cited in docs/diagnostics.md.
"""

from __future__ import annotations

from melfa.kin.reach import reach_diagnostics
from melfa.lang import check
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.points_read import parse_points
from melfa.lang.project import check_project


def found(text: str, points: tuple[str, ...] = ()) -> list[Diagnostic]:
    return check(text, points)


def rules(text: str, points: tuple[str, ...] = ()) -> list[str]:
    return [d.rule for d in found(text, points)]


# --- false alarms on valid MELFA BASIC IV ------------------------------------------------


def test_relm_without_argument_is_valid() -> None:
    # The reference's own GETM example ends with a plain RELM [S1 RELM, GETM].
    assert rules("10 GETM 1\n20 MOV P1\n60 RELM\n", ("P1",)) == []
    assert rules("10 RELM 1\n") == []


def test_fractional_overrides_are_valid_but_zero_and_over_100_are_not() -> None:
    assert rules("10 OVRD 0.5\n20 JOVRD 0.01\n30 OVRD 100\n") == []
    bad = found("10 OVRD 0\n20 JOVRD 100.5\n30 OVRD -1\n")
    assert [(d.line, d.rule, d.severity) for d in bad] == [
        (1, "value-out-of-range", Severity.ERROR),
        (2, "value-out-of-range", Severity.ERROR),
        (3, "value-out-of-range", Severity.ERROR),
    ]
    assert "above 0" in (bad[0].suggestion or "")


def test_a_type_suffix_does_not_defeat_a_declaration() -> None:
    assert rules("10 DEF INTE PATTERN\n20 PATTERN% = 3\n30 M1 = PATTERN% + 1\n") == []


def test_return_1_of_an_interrupt_below_a_gosub_used_as_a_loop() -> None:
    text = (
        "10 DEF ACT 1, M_IN(1) = 1 GOSUB *IRQ\n"
        "20 ACT 1 = 1\n"
        "30 *MAIN\n"
        "40 M2 = M2 + 1\n"
        "50 GOSUB *MAIN\n"
        "60 *IRQ\n"
        "70 M1 = 1\n"
        "80 RETURN 1\n"
    )
    assert rules(text) == []
    # A real mismatch is still found: a GOSUB routine ending in RETURN 1.
    assert rules("10 GOSUB *SUB\n20 END\n30 *SUB\n40 RETURN 1\n") == ["interrupt-return"]


def test_act1_without_a_space_is_a_variable_and_warned() -> None:
    (d,) = found(
        "10 DEF ACT 1, M_IN(1) = 1 GOSUB *IRQ\n20 ACT1 = 1\n30 END\n40 *IRQ\n50 RETURN 1\n"
    )
    assert (d.line, d.rule, d.severity) == (2, "act-without-space", Severity.WARNING)
    assert d.suggestion == "Write ACT 1 = … with a space to switch interrupt 1."
    assert rules("10 ACT 1 = 1\n") == []


# --- points files read like programs ------------------------------------------------------


def test_points_names_follow_the_program_name_rule() -> None:
    text = "P1_Align=(400,0,600,180,0,180)(7,0)\n"
    program = "10 MOV P1_Align\n"
    report = check_project([program], [text])
    assert report.programs == ((),) and report.points == ((),)


def test_points_know_the_programs_def_pos() -> None:
    points = "get_box=(400,0,600,180,0,180)(7,0)\nJ_home=(0,0,90,0,90,0)\n"
    program = "10 DEF POS GET_BOX\n20 MOV get_box\n"
    report = check_project([program], [points])
    assert [d.rule for d in report.points[0]] == ["points-name"]  # J_home: external, a warning
    assert report.points[0][0].severity is Severity.WARNING
    alone = parse_points("get_box=(400,0,600,180,0,180)(7,0)\n")
    assert [d.rule for d in alone.diagnostics] == ["points-name"]  # without its program


def test_array_elements_in_a_points_file() -> None:
    f = parse_points("PMAG(1)=(400,0,600,180,0,180)(7,0)\nPMAG(2)=(400,0,500,180,0,180)(7,0)\n")
    assert (f.diagnostics, [p.name for p in f]) == ((), ["PMAG(1)", "PMAG(2)"])
    twice = parse_points("PMAG(1)=(1,2,3,4,5,6)(7,0)\npmag(1)=(1,2,3,4,5,6)(7,0)\n")
    assert [d.rule for d in twice.diagnostics] == ["points-duplicate"]


def test_no_data_placeholders_and_tool_data_get_no_reach_warning() -> None:
    points = (
        "PFAR=(3000,0,600,180,0,180)(,)\n"  # RT ToolBox's (,): no data
        "PHAND=(0,0,2500,0,0,0)(7,0)\n"  # tool data, far from any reach
        "PGO=(3000,0,600,180,0,180)(7,0)\n"  # a real target out of reach
    )
    program = "10 TOOL PHAND\n20 MOV PGO\n30 MOV PFAR\n"
    report = check_project([program], [points], reach_diagnostics)
    assert report.programs == ((),)
    assert [(d.line, d.rule) for d in report.points[0]] == [
        (1, "points-no-data"),
        (3, "point-out-of-reach"),
    ]


def test_a_command_log_or_a_program_is_named_once() -> None:
    log = "1;1;EXECP1=(400,0,600,180,0,180)(6,0)\n1;1;EXECMOV P1\n1;1;EXECP2=(1,2,3,4,5,6)(6,0)\n"
    (d,) = parse_points(log).diagnostics
    assert (d.rule, d.line) == ("points-wrong-file", 1)
    assert "R-protocol command log" in d.message
    (d,) = parse_points("10 MOV P1\n20 HOPEN 1\n30 END\n").diagnostics
    assert (d.rule, "program" in d.message) == ("points-wrong-file", True)


# --- MELFA BASIC V: each construct named once, nothing after it ---------------------------


def v_findings(text: str) -> list[tuple[int, str]]:
    return [(d.line, d.rule) for d in found(text)]


def test_numbered_tool_and_base_frames_are_v() -> None:
    (d,) = found("10 TOOL 1\n")
    assert (d.rule, d.column) == ("melfa-basic-v", 9)
    assert "numbered tool frame" in d.message and "P_NTOOL" in (d.suggestion or "")
    assert rules("10 BASE 0\n") == ["melfa-basic-v"]
    # IV's forms: a position, a position variable, the system's default.
    assert rules("10 TOOL (0,0,100,0,0,0)\n20 BASE P_NBASE\n30 DEF POS GRP1\n40 TOOL GRP1\n") == []


def test_a_general_wait_condition_is_v() -> None:
    assert rules("10 WAIT M_IN(1) = 1\n20 WAIT M1 = -2\n") == []
    (d,) = found("10 WAIT M_IN8(100) <> 0\n")
    assert d.rule == "melfa-basic-v" and "loop" in (d.suggestion or "")
    assert rules("10 WAIT (M_IN(10) = 0 AND M1 < 6) OR M_IN(11) = 1\n") == ["melfa-basic-v"]


def test_v_status_variables_are_named_once_per_name() -> None:
    text = '10 C_COM(1) = "ETH:192.168.0.2"\n20 M1 = M_PI\n30 M2 = M_PI * 2\n'
    ds = [d for d in found(text) if d.rule == "melfa-basic-v"]
    assert [d.line for d in ds] == [1, 2]
    assert ds[1].suggestion == "Write the number, 3.14159265, or compute it as 4 * ATN(1)."
    assert "Not available in IV" in (ds[0].suggestion or "")


def test_vision_commands_are_v_never_a_typo_guess() -> None:
    (d,) = found('10 NVOpen "COM2:" As #1\n')
    assert d.rule == "melfa-basic-v" and "HOPEN" not in d.message + (d.suggestion or "")
    assert "Not available in IV" in (d.suggestion or "")
    assert rules("10 DEF LONG MX\n") == ["melfa-basic-v"]


def test_a_function_block_is_named_once_and_its_calls_are_not_arrays() -> None:
    text = (
        "10 Function M Add(M a, M b)\n"
        "20 Add = a + b\n"
        "30 Exit Function\n"
        "40 FEnd\n"
        "50 M2 = Add(1, 2)\n"
        "60 M3 = Add(M2, 4)\n"
    )
    assert v_findings(text) == [(1, "melfa-basic-v")]


def test_the_hash_suffix_is_explained() -> None:
    ds = [
        d
        for d in found("10 MTimeout# = 1.0#\n20 M1 = MTimeout# + 1\n")
        if d.rule != "melfa-basic-v-program"
    ]
    assert [(d.line, d.column, d.rule) for d in ds] == [
        (1, 4, "melfa-basic-v"),
        (1, 16, "melfa-basic-v"),
    ]
    assert "double-precision" in ds[0].message and "DEF DOUBLE" in (ds[0].suggestion or "")


def test_a_mostly_v_file_is_said_to_look_like_v_once() -> None:
    text = "10 BASE 1\n20 WAIT M_IN8(100) <> 0\n30 TOOL 2\n40 HOPEN 9\n"
    summaries = [d for d in found(text) if d.rule == "melfa-basic-v-program"]
    assert len(summaries) == 1 and summaries[0].line == 1
    assert "3 of its 4 errors" in summaries[0].message
    assert summaries[0].severity is Severity.WARNING
    # One V construct among IV mistakes is not a V program.
    assert "melfa-basic-v-program" not in rules("10 BASE 1\n20 HOPEN 9\n30 OVRD 0\n")


def test_a_v_construct_used_again_is_named_at_its_first_use() -> None:
    text = (
        "10 Fsc On, 0, 0, 1\n20 MOV P1\n30 Fsc Off\n40 Fsc Off\n"
        "50 P_FsStf0 = P1\n60 M1 = M_FsCod0\n"
    )
    ds = [d for d in found(text, ("P1",)) if d.rule == "melfa-basic-v"]
    assert [d.line for d in ds] == [1, 5]
    assert ds[0].message.endswith("(also on lines 3, 4)")
    assert "every P_Fs…, M_Fs… name" in ds[1].message


# --- mistakes that are cheap to catch -----------------------------------------------------


def test_a_position_stored_in_a_numeric_name() -> None:
    # `DEF POS FP` commented out: the simulator stops with L4390 at line 20.
    (d,) = found("10 ' DEF POS FP\n20 FP = (400,0,600,180,0,180)(7,0)\n30 MOV FP\n")
    assert (d.line, d.rule, d.code, d.severity) == (
        2,
        "position-in-number",
        "L4390",
        Severity.ERROR,
    )
    assert d.suggestion == "Declare it first with DEF POS FP, or give it a name that starts with P."
    assert rules("10 DEF POS FP\n20 FP = (400,0,600,180,0,180)(7,0)\n") == []
    assert rules("10 PX = (400,0,600,180,0,180)(7,0)\n20 P_01 = PX\n") == []


def test_degrees_written_into_a_radian_element() -> None:
    (d,) = found("10 PH1 = P_CURR\n20 PH1.C = 70\n")
    assert (d.line, d.rule, d.severity) == (2, "angle-in-degrees", Severity.WARNING)
    assert d.suggestion == "Convert it: RAD(70) gives 1.2217 rad."
    assert rules("10 PH1 = P_CURR\n20 PH1.C = RAD(70)\n30 PH1.A = -3.1\n40 PH1.X = 700\n") == []


def test_a_goto_that_leaves_a_gosub_routine() -> None:
    text = (
        "10 *LOOP\n20 GOSUB *SUB\n30 GOTO *LOOP\n"
        "40 *SUB\n50 IF M_IN(1) = 1 THEN GOTO *LOOP\n60 IF M_IN(2) = 1 THEN *SKIP\n"
        "70 RETURN\n80 *SKIP\n90 M1 = 2\n100 RETURN\n"
    )
    (d,) = found(text)
    assert (d.line, d.column, d.rule, d.severity) == (5, 29, "goto-out-of-gosub", Severity.WARNING)
    assert "*SUB" in d.message
    # A GOSUB used as a loop has no RETURN: not a routine.
    assert rules("10 *MAIN\n20 M1 = M1 + 1\n30 GOSUB *MAIN\n40 GOTO *MAIN\n") == []


def test_leaving_a_routine_for_code_that_stops_the_program_leaks_nothing() -> None:
    text = (
        "10 GOSUB *TAKE\n20 END\n30 *TAKE\n40 IF M1 <= 0 THEN *EMPTY\n50 RETURN\n"
        "60 *EMPTY\n70 ERROR 9100\n"
    )
    assert rules(text) == []
