"""Step numbers the controller reports, mapped back to the lines of the user's text."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from melfa.lang.numbering import controller_text, is_numbered, source_line, step_lines

STATEMENTS = st.sampled_from(
    ["MOV P1", "M1 = M1 + 1", "' a comment", "*LOOP", "HOPEN 1", "", "  ", "DLY 0.5"]
)


def test_unnumbered_lines_map_through_the_upload_numbering() -> None:
    text = "SERVO ON\n\n*LOOP\n  MOV P1\nGOTO *LOOP\n"
    assert step_lines(text) == {10: 1, 30: 3, 40: 4, 50: 5}
    assert source_line(text, 40) == 4
    assert source_line(text, 20) is None  # a blank line has no step
    assert source_line(text, None) is None


def test_a_numbered_text_keeps_its_own_numbers() -> None:
    text = "5 SERVO ON\n\n7 MOV P1\n100 END\n"
    assert is_numbered(text)
    assert step_lines(text) == {5: 1, 7: 3, 100: 4}
    assert controller_text(text) == text


def test_a_partly_numbered_text_is_renumbered_as_the_upload_does() -> None:
    text = "SERVO ON\n7 MOV P1\nGOTO 7\n"  # editor form: jump targets keep their number
    assert not is_numbered(text)
    assert controller_text(text) == "10 SERVO ON\n20 MOV P1\n30 GOTO 20\n"
    assert step_lines(text) == {10: 1, 20: 2, 30: 3}


@given(st.lists(STATEMENTS, max_size=30))
def test_every_step_of_the_controller_text_maps_to_its_own_line(lines: list[str]) -> None:
    text = "\n".join(lines)
    sent = controller_text(text).split("\n")
    mapping = step_lines(text)
    for number, line in mapping.items():
        assert sent[line - 1].split()[0] == str(number)
        assert lines[line - 1].strip()  # never a blank line
    assert len(mapping) == sum(1 for s in lines if s.strip())
