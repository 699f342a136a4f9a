"""Properties over any input: never raises, positions inside the text, lossless lexing."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from melfa.lang import check, parse, tokenize, untokenize
from melfa.lang.project import check_project

VALID = (Path(__file__).parent / "cases" / "catalogue_valid.mb4").read_text(encoding="utf-8")
VALID_LINES = VALID.splitlines()
THESIS = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"

# Text made of the language's own pieces is far likelier to reach deep parser paths than
# uniformly random characters.
PIECES = st.sampled_from(
    [
        "MOV", "MVS", "IF", "THEN", "ELSE", "FOR", "NEXT", "WHILE", "WEND", "SELECT", "CASE",
        "END", "DEF", "POS", "INTE", "GOTO", "*L", "P1", "M1", "(", ")", ",", "=", "+", "-",
        "*", "^", "<>", ".X", "1", "2.5", "&H1F", '"s"', "'c", "\n", "\r\n", "\r", " ", "\t",
        "PLT", "WTH", "TYPE", "TO", "IS", "NOT", "AND", "é", "\x00", "10 ",
        # names the symbol tables look up (arrays, DEF FN, system variables, interrupts, V)
        "DIM", "MA(", "FNX(", "DEF FNX(", "M_IN(", "M_INN", "P_CURR", "ACT", "DEF ACT 1,",
        "GOSUB", "RETURN", "RETURN 1", "SIN(", "ATN2(", "C1$", "ElseIf", "Const", "Fsc",
    ]
)  # fmt: skip
TEXTS = st.one_of(
    st.text(max_size=200),
    st.lists(PIECES, max_size=60).map("".join),
)


def lines_of(text: str) -> list[str]:
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


def assert_inside(text: str) -> None:
    lines = lines_of(text)
    for d in check(text, ["P1"]):
        assert d.rule != "internal-error", d.message
        assert 1 <= d.line <= len(lines)
        assert d.end_line == d.line
        assert 1 <= d.column <= d.end_column <= len(lines[d.line - 1]) + 1


@given(TEXTS)
def test_lexer_round_trips(text: str) -> None:
    tokens = tokenize(text)
    assert untokenize(tokens) == text
    assert tokens[-1].kind.name == "EOF"


@given(TEXTS)
def test_check_never_raises_and_points_inside(text: str) -> None:
    assert_inside(text)


@given(TEXTS)
def test_one_tree_line_per_text_line(text: str) -> None:
    assert len(parse(text).lines) == len(lines_of(text))


@st.composite
def mutated_program(draw: st.DrawFn) -> str:
    """A valid program with a few random edits: delete, insert or swap characters/lines."""
    lines = list(draw(st.sampled_from([VALID_LINES, THESIS.splitlines()])))
    for _ in range(draw(st.integers(1, 4))):
        index = draw(st.integers(0, len(lines) - 1))
        line = lines[index]
        action = draw(st.sampled_from(["delete", "insert", "drop-line", "dup-line", "swap"]))
        pos = draw(st.integers(0, len(line)))
        if action == "delete" and line:
            lines[index] = line[:pos] + line[pos + 1 :]
        elif action == "insert":
            lines[index] = line[:pos] + draw(PIECES) + line[pos:]
        elif action == "drop-line":
            del lines[index]
        elif action == "dup-line":
            lines.insert(index, line)
        elif action == "swap":
            other = draw(st.integers(0, len(lines) - 1))
            lines[index], lines[other] = lines[other], lines[index]
        if not lines:
            lines = [""]
    return "\n".join(lines) + draw(st.sampled_from(["", "\n", "\r\n"]))


@given(mutated_program())
def test_mutated_programs(text: str) -> None:
    assert untokenize(tokenize(text)) == text
    assert_inside(text)


def test_valid_inputs_are_clean() -> None:
    assert check(VALID, ["P1", "P2", "P3", "P4", "P5", "J0"]) == []
    assert check(THESIS, ["PA", "PB"]) == []


@given(TEXTS, TEXTS)
def test_project_check_never_raises_and_points_inside(program: str, points: str) -> None:
    """check_project (the CLI's and the web's) on any program and any points file."""
    report = check_project([program], [points])
    for text, found in ((program, report.programs[0]), (points, report.points[0])):
        lines = lines_of(text)
        for d in found:
            assert d.rule != "internal-error", d.message
            assert 1 <= d.line <= len(lines)
            assert 1 <= d.column <= d.end_column <= len(lines[d.line - 1]) + 1
