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


def test_moved_trees_are_the_parse_to_the_last_field() -> None:
    """A repeated line, one shifted by a line inserted above, a step number of the same width:
    the moved copy is the parser's tree, with every span and the name as written (fields
    `==` leaves out) the same, over the golden corpus read one after another by one cache."""
    from tests.lang.test_golden import corpus

    cache = LineCache()
    for text in corpus().values():
        for variant in (text, "' inserted\n" + text, text + text):
            assert repr(cache.parse(variant)) == repr(parse(variant))


def test_a_step_number_of_the_same_width_is_moved_with_its_value() -> None:
    cache = LineCache()
    text = "10 HOPEN 1\n20 HOPEN 1\n100 HOPEN 1\n30 HOPEN 1\n  40 HOPEN 1\n50HOPEN 1\n60HOPEN 1\n"
    program = cache.parse(text)
    assert repr(program) == repr(parse(text))
    assert [line.number for line in program.lines] == [10, 20, 100, 30, 40, 50, 60, None]


def test_skipping_repeated_lines_changes_no_finding() -> None:
    """`check` skips the analysis of a line written exactly like an earlier one that got no
    finding; every finding is still the one of the whole analysis (`check_ast` without the
    repeats), on the golden corpus, each text doubled and its lines shuffled together."""
    import random

    from melfa.lang.check import check_ast
    from tests.lang.test_golden import POINTS, corpus

    rng = random.Random(25)
    texts = list(corpus().values())
    for text in texts:
        lines = text.splitlines(keepends=True) + rng.choice(texts).splitlines(keepends=True)
        rng.shuffle(lines)
        for variant in (text, text + text, "".join(lines)):
            assert check(variant, POINTS) == check_ast(parse(variant), POINTS)


@given(
    st.lists(
        st.sampled_from(
            [
                "10 MOV P1",
                "M1 = 2",
                "'c",
                "",
                "\r",
                "\n",
                "\r\n",
                "\v",
                "\f",
                "\x1c",
                "\x85",
                "\u2028",
                " ",
            ]
        ),
        max_size=12,
    ),
    st.booleans(),
)
def test_lines_end_where_the_lexer_ends_them(parts: list[str], many: bool) -> None:
    """Only CR, LF and CR LF end a line, as the lexer reads it (str.splitlines would end one
    at a form feed or U+2028 too), for a few lines and for many (fastline's way)."""
    text = "".join(parts) * (30 if many else 1)
    assert LineCache().parse(text) == parse(text)
