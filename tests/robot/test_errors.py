"""Refusals read like a person wrote them: the statement as typed, the number once."""

from __future__ import annotations

from melfa.robot import ControllerError, UploadRefused
from melfa.robot.errors import describe, statement_of


def test_exec_refusal_shows_the_statement_and_the_number_once() -> None:
    exc = ControllerError(
        2600, "L2600 Position data exceeds the limit", command="EXECMOV P_CURR*(0,0,-5000,0,0,0)"
    )
    assert str(exc) == (
        "the controller refused `MOV P_CURR*(0,0,-5000,0,0,0)`: "
        "L2600 Position data exceeds the limit"
    )
    assert exc.statement == "MOV P_CURR*(0,0,-5000,0,0,0)"
    assert str(exc).count("2600") == 1


def test_other_commands_are_shown_as_sent() -> None:
    assert statement_of("SRVON") == "SRVON"
    assert str(ControllerError(1630, "C1630 Cannot servo ON during an error", command="SRVON")) == (
        "the controller refused `SRVON`: C1630 Cannot servo ON during an error"
    )


def test_a_text_without_its_number_gets_it() -> None:
    assert describe(9100, "Pila buida") == "error 9100: Pila buida"
    assert describe(9100, "") == "error 9100"
    assert (
        str(ControllerError(9100, "Pila buida")) == "the controller refused: error 9100: Pila buida"
    )


def test_upload_refusal_names_source_line_and_column() -> None:
    exc = UploadRefused(4220, "L4220 Syntax error", line=2, column=5, text="20 MOV")
    assert (
        str(exc)
        == "the controller refused program line 2, column 5: L4220 Syntax error\n    20 MOV"
    )
