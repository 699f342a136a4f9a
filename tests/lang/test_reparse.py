"""`melfa.lang.reparse`: a cached parse is the parse, whatever the cache saw before."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from melfa.lang import check, parse, tokenize
from melfa.lang.reparse import LineCache
from tests.lang.test_properties import TEXTS, VALID_LINES

EDITS = st.lists(
    st.tuples(st.integers(0, 40), st.sampled_from(["", "x", " ", "\n", "*L", "'c", "10 "])),
    max_size=6,
)


@given(TEXTS, EDITS)
def test_a_cached_parse_equals_the_parse_after_any_edits(text: str, edits: list) -> None:
    """One cache through a run of edits (characters typed, lines split): every tree equals
    the parser's own, lines the cache kept and lines it read again alike."""
    cache = LineCache()
    for where, typed in [(0, ""), *edits]:
        at = min(where * 7, len(text))
        text = text[:at] + typed + text[at:]
        assert cache.parse(text) == parse(text)


@given(st.lists(st.sampled_from(VALID_LINES), min_size=1, max_size=30), st.integers(0, 29))
def test_a_line_that_moves_is_read_again(lines: list[str], cut: int) -> None:
    """A line inserted above shifts the rest: their trees carry new line numbers."""
    cache = LineCache()
    text = "\n".join(lines) + "\n"
    assert cache.parse(text) == parse(text)
    moved = "\n".join([*lines[:cut], "' a new line", *lines[cut:]]) + "\n"
    assert cache.parse(moved) == parse(moved)


def test_a_line_whose_message_needs_the_files_labels_is_never_kept() -> None:
    """`PICK` alone is "Label needs to start with *" only in a file that jumps to *PICK."""
    cache = LineCache()
    with_jump = "GOTO *PICK\nPICK\n"
    without = "MOV P1\nPICK\n"
    assert cache.parse(with_jump) == parse(with_jump)
    assert cache.parse(without) == parse(without)
    assert cache.parse(with_jump).lines[1].issues[0].rule == "label-without-star"


def test_the_cache_is_bounded() -> None:
    cache = LineCache(limit=100)
    for n in range(10):
        cache.parse("".join(f"M{n} = {i}\n" for i in range(60)))
    assert len(cache) <= 100


def test_spaces_at_the_end_of_a_file_are_no_statement() -> None:
    """Found by the cache's equality: text ending in spaces without a line end lexed two
    EOFs, and the last line read as a statement that was missing."""
    assert check("10 MOV P1\n   ", ["P1"]) == []
    assert [t.kind.name for t in tokenize("  ")] == ["EOF"]
