"""Minimal reproductions of what real MELFA programs showed the checker (issue 25).

Each test is the smallest program that showed a false alarm, a missed mistake or a wrong
reading of MELFA BASIC V; the reference each rule follows is cited in docs/diagnostics.md.
"""

from __future__ import annotations

from melfa.kin.reach import reach_diagnostics
from melfa.lang import check
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.points import parse_points
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
