"""Keyword case: one spelling for the language's words, the user's names and text untouched."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from melfa.lang.format import LineNumbers, format_program, normalize_case
from melfa.lang.lexer import tokenize
from melfa.lang.tokens import TokenKind


def test_keywords_functions_and_elements_are_upper_cased() -> None:
    assert normalize_case("Mov pGoal, -80") == "MOV pGoal, -80"
    assert normalize_case("ptemp1.a=Rad(MPosA/100)") == "ptemp1.A=RAD(MPosA/100)"
    assert normalize_case("if m1 > 1 and not m2 then *Loop else goto 100") == (
        "IF m1 > 1 AND NOT m2 THEN *Loop ELSE GOTO 100"
    )
    assert normalize_case("def inte n\nm_out(&h0f) = 1") == "DEF INTE n\nm_out(&H0F) = 1"


def test_names_labels_strings_and_comments_are_kept_as_written() -> None:
    text = "*Inici\nC1$ = \"mov p1\"\n' mov to the piràmide\nm_out(17) = 1 ' hopen"
    assert normalize_case(text) == text


def test_rem_word_is_upper_cased_but_its_text_is_not() -> None:
    assert normalize_case("rem mov here") == "REM mov here"


def test_spacing_tabs_and_line_ends_are_kept() -> None:
    assert (
        normalize_case("10\tmov  p1 ,\t-50  \r\n20 end\r\n") == "10\tMOV  p1 ,\t-50  \r\n20 END\r\n"
    )


def test_broken_lines_are_formatted_without_damage() -> None:
    assert normalize_case('mov p1 ?? "open string\nhopen 1') == 'MOV p1 ?? "open string\nHOPEN 1'


def test_format_program_numbers_and_strips() -> None:
    assert format_program("servo on\n*l\ngoto *l", LineNumbers.NUMBER).text == (
        "10 SERVO ON\n20 *l\n30 GOTO *l"
    )
    assert format_program("10 servo on\n20 end", LineNumbers.STRIP).text == "SERVO ON\nEND"
    assert format_program("10 servo on", LineNumbers.KEEP).text == "10 SERVO ON"


def test_format_program_refuses_rather_than_guess() -> None:
    result = format_program("mov p1\ngoto 30", LineNumbers.NUMBER)
    assert not result.ok
    assert result.text == "mov p1\ngoto 30"
    assert result.diagnostics[0].code == "L4230"


_WORDS = st.sampled_from(
    ["mov", "Mvs", "p1", "pGoal", "*loop", '"Text mov"', "' com mov", "+", ",", "(", ")",
     ".x", "&h1f", "10", "1.5", "sin", "m_in", "?", " ", "\t", "\n", "then", "rem x"]
)  # fmt: skip


@given(st.lists(_WORDS, max_size=30).map(" ".join))
def test_only_the_case_of_keywords_changes(text: str) -> None:
    out = normalize_case(text)
    assert out.upper() == text.upper()
    before, after = tokenize(text), tokenize(out)
    assert [t.kind for t in before] == [t.kind for t in after]
    for a, b in zip(before, after, strict=True):
        if a.kind in (TokenKind.IDENT, TokenKind.LABEL, TokenKind.STRING, TokenKind.ERROR):
            assert a.text == b.text
    assert normalize_case(out) == out  # idempotent


def test_def_io_types_are_keywords() -> None:
    text = "def io mSensor = bit, 900\ndef io mPort = byte, 10, &h0f\ndef io mW = word, 16"
    assert normalize_case(text) == (
        "DEF IO mSensor = BIT, 900\nDEF IO mPort = BYTE, 10, &H0F\nDEF IO mW = WORD, 16"
    )
    assert normalize_case("def io mI = integer, 32\ndef io mD = dword, 32") == (
        "DEF IO mI = INTEGER, 32\nDEF IO mD = DWORD, 32"
    )


def test_def_io_still_parses_in_any_case() -> None:
    from melfa.lang import ast as A  # noqa: N812
    from melfa.lang import check, parse

    for word in ("bit", "Byte", "WORD", "integer", "DWord"):
        stmt = parse(f"DEF IO MX = {word}, 900, &H0F").lines[0].statement
        assert isinstance(stmt, A.DefIO), word
        assert stmt.io_type is A.IOType(word.upper())
    assert check("DEF IO MX = BIT, 900\nMX = 1\n") == []
    [d] = check("DEF IO MX = BITS, 900\n")
    assert d.suggestion == "Write BIT instead of BITS."
