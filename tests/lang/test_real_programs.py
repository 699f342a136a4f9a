"""Minimal reproductions of what real MELFA programs showed the checker (issue 25).

Each test is the smallest program that showed a false alarm, a missed mistake or a wrong
reading of MELFA BASIC V; the reference each rule follows is cited in docs/diagnostics.md.
"""

from __future__ import annotations

from melfa.lang import check
from melfa.lang.diagnostics import Diagnostic, Severity


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
