import functools

import pytest
from hypothesis import given
from hypothesis import strategies as st

from melfa.protocol import REQUEST_LIMIT, VT, LocalProtocolError, chunk_emdat

PREFIX = len("1;9;EMDAT")
line_text = st.text(alphabet=st.characters(min_codepoint=32, max_codepoint=126), min_size=1)


def minimal_count(sizes: list[int], room: int) -> int:
    """Exhaustive optimum by dynamic programming over split points."""

    @functools.cache
    def best(i: int) -> int:
        if i == len(sizes):
            return 0
        out, used = 10**9, -1
        for j in range(i, len(sizes)):
            used += sizes[j] + 1
            if used > room:
                break
            out = min(out, 1 + best(j + 1))
        return out

    return best(0)


@given(st.lists(line_text.filter(lambda s: len(s) <= REQUEST_LIMIT - PREFIX), max_size=40))
def test_chunks_fit_keep_lines_whole_in_order_and_are_minimal(lines: list[str]) -> None:
    chunks = chunk_emdat(lines)
    for chunk in chunks:
        assert len(chunk.request.to_bytes()) - 1 <= REQUEST_LIMIT
        assert chunk.request.command == "EMDAT" + VT.join(chunk.lines)
        assert chunk.request.slot == 9
    assert [line for c in chunks for line in c.lines] == lines
    assert [c.start for c in chunks] == [
        sum(len(c.lines) for c in chunks[:i]) for i in range(len(chunks))
    ]
    assert len(chunks) == minimal_count([len(s) for s in lines], REQUEST_LIMIT - PREFIX)


def test_exact_fit_boundary() -> None:
    room = REQUEST_LIMIT - PREFIX
    a, b = "A" * 100, "B" * (room - 101)
    assert len(chunk_emdat([a, b])) == 1
    assert len(chunk_emdat([a, b + "C"])) == 2
    assert len(chunk_emdat(["X" * room])) == 1


def test_line_too_long_names_the_line() -> None:
    lines = ["10 MOV P1", "20 " + "X" * 300]
    with pytest.raises(LocalProtocolError, match=r"line 2 \('20 XXX"):
        chunk_emdat(lines)


@pytest.mark.parametrize("bad", ["", "10 A\x0bB", "10 A\rB"])
def test_unusable_lines(bad: str) -> None:
    with pytest.raises(LocalProtocolError, match="line 1"):
        chunk_emdat([bad])


def test_refused_item_maps_back_to_the_line() -> None:
    lines = [f"{10 * i} MOV P{i}" for i in range(1, 80)]
    chunks = chunk_emdat(lines)
    assert len(chunks) > 2
    second = chunks[1]
    assert lines[second.line_index(3)] == second.lines[2]
