"""MELFA BASIC V recognised, not accepted: one clear message per construct that says it is
V, that the CR2B-574 runs IV, and how to write it in IV; no cascade; never a typo guess that
changes the meaning (§0 of ../shared/docs/melfa-basic-iv.md)."""

from __future__ import annotations

import pytest

from melfa.lang import check
from melfa.lang.model import V_CONSTRUCTS, Dialect, foreign_constructs


def test_elseif_is_v_and_never_else() -> None:
    """§0, §4.5: ElseIf is V; "Did you mean ELSE?" would change the program."""
    program = "IF M_IN(8) = 1 THEN\nMOV P1\nElseIf M_IN(9) = 1 Then\nMOV P2\nELSE\nMOV P3\nENDIF\n"
    [d] = check(program, ["P1", "P2", "P3"])
    assert (d.line, d.rule, d.code) == (3, "melfa-basic-v", "L4220")
    assert "MELFA BASIC V" in d.message and "CR2B-574" in d.message
    assert "ELSE instead" not in (d.suggestion or "")
    assert d.suggestion == "Write ELSE, then a new IF … THEN block inside it with its own ENDIF."


@pytest.mark.parametrize(
    ("line", "what"),
    [
        ("Const Def Inte MAXCNT = 12", "Const"),
        ("Fsc On, 0, 0, 1", "Fsc"),
        ("MvTune 2", "MvTune"),
        ("Function M FAdd(M1)", "Function"),
        ("FEnd", "Function"),
        ('Include "LIB"', "Include"),
    ],
)
def test_each_v_construct_gets_one_message(line: str, what: str) -> None:
    """§0, §4.6: one finding per construct, none of "expected '=' after Fsc"."""
    [d] = check(f"{line}\nEND\n")
    assert d.rule == "melfa-basic-v"
    assert d.message.startswith(what)
    assert "expected '='" not in d.message
    assert d.suggestion


def test_a_v_word_used_as_a_variable_is_still_a_variable() -> None:
    """§2.1: `FSC = 1` assigns a variable (no V statement starts with `=`)."""
    assert [d.rule for d in check("MFSC = 1\n")] == []


def test_iv_is_the_only_dialect_and_v_constructs_are_foreign_to_it() -> None:
    """§0: the model has a dialect switch; V would be a second Dialect."""
    assert list(Dialect) == [Dialect.IV]
    assert foreign_constructs(Dialect.IV) is V_CONSTRUCTS
    assert {"ELSEIF", "CONST", "FSC"} <= set(V_CONSTRUCTS)


def test_long_v_names_are_reported_once() -> None:
    """§2.1: IV names have at most 8 characters (V allows more)."""
    found = check("PEndOFConveyor = P1\nMOV PEndOFConveyor\n", ["P1"])
    assert [d.rule for d in found] == ["name-too-long"]
