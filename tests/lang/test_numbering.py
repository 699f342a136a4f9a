"""Step numbers off and on again, without changing where any jump goes."""

from __future__ import annotations

import re

import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.lang.diagnostics import Severity
from melfa.lang.numbering import (
    NumberingError,
    number_lines,
    references,
    renumber,
    strip,
    strip_numbers,
)

THESIS_SAMPLE = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"

JUMPY = """\
10 SERVO ON
20 ' Posició inicial
30 *LOOP
40 IF M1>10 THEN 70 ELSE 30
50 ON M1 GOTO 30, *LOOP, 60
60 DEF ACT 1, M_IN(1)=1 GOSUB 30, S
70 END
"""


def test_thesis_sample_strips_to_bare_statements() -> None:
    assert strip_numbers(THESIS_SAMPLE) == (
        "SERVO ON\nSPD 20\nOVRD 20\nMOV Pa\nMOV Pb\nHOPEN 1\nEND\n"
    )


def test_numbering_bare_statements_gives_the_thesis_sample() -> None:
    assert number_lines(strip_numbers(THESIS_SAMPLE)) == THESIS_SAMPLE


def test_strip_keeps_the_numbers_that_jumps_use() -> None:
    stripped = strip_numbers(JUMPY)
    assert stripped.splitlines() == [
        "SERVO ON",
        "' Posició inicial",
        "30 *LOOP",
        "IF M1>10 THEN 70 ELSE 30",
        "ON M1 GOTO 30, *LOOP, 60",
        "60 DEF ACT 1, M_IN(1)=1 GOSUB 30, S",
        "70 END",
    ]
    assert number_lines(stripped) == JUMPY


def test_renumbering_1_2_3_rewrites_references() -> None:
    assert number_lines("1 MOV P1\n2 HOPEN 1\n3 GOTO 2\n") == "10 MOV P1\n20 HOPEN 1\n30 GOTO 20\n"
    assert number_lines(strip_numbers("1 MOV P1\n2 HOPEN 1\n3 GOTO 2\n")) == (
        "10 MOV P1\n20 HOPEN 1\n30 GOTO 20\n"
    )


@pytest.mark.parametrize(
    ("before", "after"),
    [
        ("5 GOSUB 7\n7 RETURN", "10 GOSUB 20\n20 RETURN"),
        ("5 IF M1 THEN 7\n7 END", "10 IF M1 THEN 20\n20 END"),
        ("5 IF M1 THEN GOTO 7 ELSE 5\n7 END", "10 IF M1 THEN GOTO 20 ELSE 10\n20 END"),
        ("5 ON M1 GOSUB 7,5, 7\n7 RETURN", "10 ON M1 GOSUB 20,10, 20\n20 RETURN"),
        ("5 ON COM(1) GOSUB 7\n7 RETURN", "10 ON COM(1) GOSUB 20\n20 RETURN"),
        ("5 DEF ACT 2, M_TIMER(1)>10.5 GOSUB 7, L\n7 RETURN 1", None),
        ("5 goto 7\n7 end", "10 goto 20\n20 end"),
    ],
)
def test_every_jump_form_is_rewritten(before: str, after: str | None) -> None:
    expected = after or "10 DEF ACT 2, M_TIMER(1)>10.5 GOSUB 20, L\n20 RETURN 1"
    assert number_lines(before) == expected


def test_numbers_in_strings_comments_and_expressions_are_left_alone() -> None:
    text = '1 C1$ = "GOTO 1"\n2 \' GOTO 1\n3 M1 = 1 + 2\n4 OVRD 1\n5 ERROR 9100\n6 DLY 1\n'
    numbered = number_lines(text)
    assert numbered == (
        '10 C1$ = "GOTO 1"\n20 \' GOTO 1\n30 M1 = 1 + 2\n40 OVRD 1\n50 ERROR 9100\n60 DLY 1\n'
    )


def test_spacing_and_indentation_are_kept() -> None:
    text = "10     radi=27\n20 MOV   P1 ,  -50   ' down\n"
    assert strip_numbers(text) == "    radi=27\nMOV   P1 ,  -50   ' down\n"
    assert number_lines(strip_numbers(text)) == text


def test_crlf_is_kept() -> None:
    assert number_lines("SERVO ON\r\nEND\r\n") == "10 SERVO ON\r\n20 END\r\n"
    assert strip_numbers("10 SERVO ON\r\n20 END\r\n") == "SERVO ON\r\nEND\r\n"


def test_blank_lines_stay_blank_and_keep_their_number_slot() -> None:
    # Step 130 is editor line 13, as in the thesis editor.
    assert number_lines("SERVO ON\n\n   \nEND\n") == "10 SERVO ON\n\n   \n40 END\n"
    numbered = "10 SERVO ON\n\n30 END\n"
    assert number_lines(strip_numbers(numbered)) == numbered


def test_comment_and_label_lines_are_numbered() -> None:
    assert number_lines("' hola\n*LOOP\nGOTO *LOOP") == "10 ' hola\n20 *LOOP\n30 GOTO *LOOP"


def test_existing_numbers_are_replaced_and_mixed_text_works() -> None:
    assert number_lines("MOV P1\n500 HOPEN 1\nGOTO 500", start=100, step=5) == (
        "100 MOV P1\n105 HOPEN 1\n110 GOTO 105"
    )


def test_a_jump_to_a_missing_step_is_reported_not_guessed() -> None:
    result = renumber("MOV P1\nGOTO 30\n")
    assert result.text == "MOV P1\nGOTO 30\n"
    [d] = result.diagnostics
    assert (d.line, d.column, d.end_column, d.code) == (2, 6, 8, "L4230")
    assert d.severity is Severity.ERROR
    assert "no step 30" in d.message
    assert d.suggestion is not None and "*NAME" in d.suggestion
    with pytest.raises(NumberingError) as err:
        number_lines("MOV P1\nGOTO 30\n")
    assert "line 2" in str(err.value)


def test_strip_warns_about_a_dangling_jump_but_still_strips() -> None:
    result = strip("10 GOTO 99\n20 END\n")
    assert result.text == "GOTO 99\nEND\n"
    assert [d.severity for d in result.diagnostics] == [Severity.WARNING]


def test_steps_out_of_order_are_refused() -> None:
    result = strip("20 MOV P1\n10 END\n")
    assert not result.ok
    assert result.text == "20 MOV P1\n10 END\n"
    assert "number order" in result.diagnostics[0].message
    with pytest.raises(NumberingError):
        number_lines("20 MOV P1\n10 END\n")


def test_duplicate_steps_are_refused() -> None:
    result = renumber("10 MOV P1\n10 END\n")
    assert not result.ok
    assert "twice" in result.diagnostics[0].message


def test_overflow_past_32767_is_reported() -> None:
    result = renumber("MOV P1\nEND\n", start=32760, step=10)
    assert not result.ok
    assert result.diagnostics[0].code == "L4420"
    assert renumber("MOV P1\nEND\n", start=32757, step=10).ok


def test_bad_start_or_step_is_our_misuse() -> None:
    with pytest.raises(ValueError):
        renumber("END", step=0)


def test_syntax_errors_do_not_stop_numbering() -> None:
    assert number_lines('MOV P1 ?? "unterminated\nGOTO') == '10 MOV P1 ?? "unterminated\n20 GOTO'


def test_empty_text() -> None:
    assert number_lines("") == ""
    assert strip_numbers("") == ""


def test_references_lists_targets_in_order() -> None:
    assert [r.number for r in references(JUMPY)] == [70, 30, 30, 60, 30]


# --- properties ------------------------------------------------------------------------

_PLAIN = [
    "MOV P1",
    "HOPEN 1",
    "' GOTO 10 in a comment",
    'C1$ = "GOSUB 20"',
    "M1 = M1 + 10",
    "*LAB",
    "",
]
_JUMPS = [
    "GOTO {a}",
    "GOSUB {a}",
    "IF M1>1 THEN {a} ELSE {b}",
    "IF M1=2 THEN GOTO {a}",
    "ON M1 GOTO {a}, *LAB, {b}",
    "DEF ACT 1, M_IN(1)=1 GOSUB {a}, S",
    "ON COM(1) GOSUB {b}",
]


@st.composite
def _numbered_programs(draw: st.DrawFn, gaps: bool = True) -> str:
    count = draw(st.integers(1, 12))
    if gaps:
        numbers: list[int] = []
        n = 0
        for _ in range(count):
            n += draw(st.integers(1, 40))
            numbers.append(n)
    else:
        numbers = [10 * (i + 1) for i in range(count)]
    lines = []
    for i, number in enumerate(numbers):
        if draw(st.booleans()):
            body = draw(st.sampled_from(_JUMPS)).format(
                a=draw(st.sampled_from(numbers)), b=draw(st.sampled_from(numbers))
            )
        else:
            body = draw(st.sampled_from(_PLAIN))
        # A unique tail makes every line's content tell which line it is.
        lines.append(f"{number} {body} ' #{i}".rstrip())
    return "\n".join(lines) + draw(st.sampled_from(["", "\n"]))


def _content(numbered: str) -> dict[int, str]:
    out = {}
    for line in numbered.splitlines():
        m = re.match(r"(\d+) (.*)", line)
        if m:
            out[int(m.group(1))] = m.group(2)
    return out


def _tail(content: str) -> str:
    return content.rsplit("' #", 1)[1]


@given(_numbered_programs(gaps=False))
def test_strip_then_number_is_the_identity_on_10_20_30(program: str) -> None:
    assert number_lines(strip_numbers(program)) == program


@given(_numbered_programs())
def test_number_after_strip_keeps_every_jump_on_the_same_line(program: str) -> None:
    result = number_lines(strip_numbers(program))
    before, after = _content(program), _content(result)
    old_refs, new_refs = references(program), references(result)
    assert len(old_refs) == len(new_refs)
    for old, new in zip(old_refs, new_refs, strict=True):
        assert _tail(before[old.number]) == _tail(after[new.number])
    # Every line is still there, in order, with its text.
    assert [_tail(c) for c in after.values()] == [_tail(c) for c in before.values()]


@given(st.text(alphabet=st.sampled_from(list("10 GOTOSUBTHEN,*L\n'\"")), max_size=60))
def test_any_text_is_numbered_or_refused_never_crashed(text: str) -> None:
    for result in (renumber(text), strip(text)):
        assert isinstance(result.text, str)
        if not result.ok:
            assert result.text == text
