"""The three-way merge behind every save made on an older revision (issue 26's three rounds
of lost lines): no line either side wrote is dropped, and one-sided edits are taken as
they are. Pure: no database."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from melfa.store.merge import edit_script, merge3

BASE = "MOV P1\nMOV P2\nHLT\nEND\n"


def test_round_1_bob_adds_a_line_alice_adds_another() -> None:
    """Round 1 of the issue: bob's line and alice's both survive."""
    bob = "MOV P1\nMOV P2\nDLY 1\nHLT\nEND\n"
    alice = "MOV P1\nHOPEN 1\nMOV P2\nHLT\nEND\n"
    merged = merge3(BASE, bob, alice)
    assert merged == "MOV P1\nHOPEN 1\nMOV P2\nDLY 1\nHLT\nEND\n"


def test_one_sided_edits_are_taken_as_they_are() -> None:
    edited = "MOV P1\nMVS P2\nHLT\nEND\n"
    assert merge3(BASE, edited, BASE) == edited
    assert merge3(BASE, BASE, edited) == edited
    assert merge3(BASE, edited, edited) == edited


def test_both_change_one_line_differently_keeps_both() -> None:
    ours = "MOV P1\nMOV P3\nHLT\nEND\n"
    theirs = "MOV P1\nMVS P2\nHLT\nEND\n"
    assert merge3(BASE, ours, theirs) == "MOV P1\nMOV P3\nMVS P2\nHLT\nEND\n"


def test_two_lines_added_at_one_place_are_both_kept() -> None:
    ours = BASE.replace("HLT\n", "HLT\nDLY 1\n")
    theirs = BASE.replace("HLT\n", "HLT\nDLY 2\n")
    assert merge3(BASE, ours, theirs) == "MOV P1\nMOV P2\nHLT\nDLY 1\nDLY 2\nEND\n"


def test_a_deleted_line_stays_deleted_when_the_other_side_did_not_touch_it() -> None:
    ours = "MOV P1\nHLT\nEND\n"
    theirs = BASE + "' done\n"
    assert merge3(BASE, ours, theirs) == "MOV P1\nHLT\nEND\n' done\n"


def test_a_last_line_without_its_end() -> None:
    assert merge3("A", "A\nB", "A\nC") == "A\nB\nC"
    assert merge3("", "x", "y") == "x\ny"


lines = st.lists(
    st.sampled_from(["MOV P1", "MOV P2", "HLT", "END", "DLY 1", "", "' x"]), max_size=8
)


def _text(parts: list[str]) -> str:
    return "".join(p + "\n" for p in parts)


@given(lines, lines, lines)
def test_no_added_line_is_dropped(base: list[str], ours: list[str], theirs: list[str]) -> None:
    """Every line a side added (beyond how often the base had it) is in the merge."""
    merged = merge3(_text(base), _text(ours), _text(theirs)).splitlines()
    for side in (ours, theirs):
        for line in set(side):
            if side.count(line) > base.count(line):
                assert line in merged


@given(lines, lines)
def test_one_side_unchanged_gives_the_other(base: list[str], other: list[str]) -> None:
    assert merge3(_text(base), _text(base), _text(other)) == _text(other)
    assert merge3(_text(base), _text(other), _text(base)) == _text(other)


@given(st.text(max_size=60), st.text(max_size=60))
def test_edit_script_turns_one_text_into_the_other(old: str, new: str) -> None:
    text = old
    for splice in edit_script(old, new):
        text = text[: splice.index] + splice.insert + text[splice.index + splice.delete :]
    assert text == new


def test_edit_script_of_a_changed_line_is_small() -> None:
    (splice,) = edit_script(BASE, BASE.replace("MOV P2", "MVS P2"))
    assert (splice.index, splice.delete, splice.insert) == (8, 2, "VS")
