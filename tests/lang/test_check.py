"""check(): static analysis findings, limits, numbering, types and robustness."""

from __future__ import annotations

import pytest

from melfa.lang import Diagnostic, Severity, check


def rules(text: str, points: tuple[str, ...] = ()) -> list[tuple[int, str]]:
    return [(d.line, d.rule) for d in check(text, points)]


THESIS_SAMPLE = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"


def test_thesis_sample_is_clean_with_its_points() -> None:
    assert check(THESIS_SAMPLE, ["Pa", "Pb"]) == []


def test_points_missing_from_the_points_file_warn() -> None:
    found = check(THESIS_SAMPLE, ["Pa"])
    assert [(d.line, d.rule, d.severity) for d in found] == [
        (5, "undefined-point", Severity.WARNING)
    ]
    assert (found[0].column, found[0].end_column) == (8, 10)
    assert "points file" in found[0].message


def test_thesis_if_example_reports_at_least_three_of_four() -> None:
    found = check("IF a < b HOPEN\nIF end < start THEN HOPEN\n")
    assert [(d.line, d.rule) for d in found] == [
        (1, "expected-then"),
        (1, "missing-argument"),
        (2, "reserved-word"),
        (2, "missing-argument"),
    ]
    assert found[0].message.startswith("Expected THEN after IF condition")


def test_thesis_label_example() -> None:
    found = check("GOTO *mylabel\nmylabel\n")
    assert [(d.line, d.rule) for d in found] == [
        (1, "undefined-label"),
        (2, "label-without-star"),
    ]
    assert found[1].message.startswith("Label needs to start with *")


def test_wihle_suggests_while_without_structure_cascade() -> None:
    found = check("WIHLE A < B\nWEND\n")
    assert [d.message for d in found] == ["Invalid statement. Did you mean WHILE instead of WIHLE?"]


def test_def_int_is_an_error_on_its_line() -> None:
    found = check("DEF DOUBLE oPx\nDEF INT npesa\nDEF POS Ppila\n")
    assert [(d.line, d.suggestion) for d in found] == [(2, "INTE")]


# --------------------------------------------------------------------------- structure

STRUCTURE = [
    ("FOR M1 = 1 TO 3\n", [(1, "for-without-next")]),
    ("NEXT\n", [(1, "next-without-for")]),
    ("FOR M1 = 1 TO 3\nNEXT M2\n", [(2, "next-mismatch")]),
    ("WHILE M1\n", [(1, "while-without-wend")]),
    ("WEND\n", [(1, "wend-without-while")]),
    ("IF M1 THEN\n", [(1, "if-without-endif")]),
    ("ENDIF\n", [(1, "endif-without-if")]),
    ("ELSE\n", [(1, "else-without-if")]),
    ("IF M1 THEN\nELSE\nELSE\nENDIF\n", [(3, "else-without-if")]),
    ("SELECT M1\n", [(1, "select-without-end")]),
    ("END SELECT\n", [(1, "end-select-without-select")]),
    ("CASE 1\n", [(1, "case-outside-select")]),
    ("SELECT M1\nCASE 1\nSELECT M2\nEND SELECT\nEND SELECT\n", [(3, "select-nested")]),
    ("BREAK\n", [(1, "break-outside-block")]),
    ("WHILE M1\nFOR M2 = 1 TO 2\nWEND\n", [(2, "for-without-next")]),
    ("FOR A = 1 TO 2\nFOR B = 1 TO 2\nNEXT B, A\n", []),
    ("FOR A = 1 TO 2\nFOR B = 1 TO 2\nNEXT\nNEXT\n", []),
    ("IF M1 THEN\n  HOPEN 1\nELSE\n  HCLOSE 1\nENDIF\n", []),
    ("SELECT M1\nCASE 1\n  BREAK\nCASE IS > 3\n  BREAK\nDEFAULT\n  BREAK\nEND SELECT\n", []),
    ("SELECT M1\nCASE 1\n  IF M2 THEN\n    BREAK\n  ENDIF\nEND SELECT\n", []),
]


@pytest.mark.parametrize(("text", "expected"), STRUCTURE)
def test_structure(text: str, expected: list[tuple[int, str]]) -> None:
    assert rules(text) == expected


def test_structure_codes() -> None:
    codes = {d.rule: d.code for d in check("NEXT\nWEND\nENDIF\nELSE\nEND SELECT\n")}
    assert codes == {
        "next-without-for": "L3230",
        "wend-without-while": "L3250",
        "endif-without-if": "L3252",
        "else-without-if": "L3255",
        "end-select-without-select": "L3254",
    }


def test_nesting_limits() -> None:
    loops = "".join(f"FOR M{i} = 1 TO 2\n" for i in range(17)) + "NEXT\n" * 17
    assert rules(loops) == [(17, "loop-nesting")]
    assert rules(loops.replace("FOR M16 = 1 TO 2\n", "").replace("NEXT\n", "", 1)) == []
    ifs = "IF M1 THEN\n" * 9 + "ENDIF\n" * 9
    assert rules(ifs) == [(9, "if-nesting")]


# ------------------------------------------------------------------------------- jumps


def test_jumps() -> None:
    text = (
        "*A\nGOTO *A\nGOSUB *B\nON M1 GOTO *A, *C\nIF M1 THEN *D ELSE *A\nDEF ACT 1, M1 GOSUB *E\n"
    )
    assert rules(text) == [
        (3, "undefined-label"),
        (4, "undefined-label"),
        (5, "undefined-label"),
        (6, "undefined-label"),
    ]


def test_jump_to_missing_step_number_is_an_error() -> None:
    found = check("10 GOTO 30\n20 GOTO 10\n")
    assert [(d.line, d.rule, d.code, d.severity) for d in found] == [
        (1, "undefined-line", "L4230", Severity.ERROR)
    ]
    assert "no step numbers" in check("GOTO 10\n")[0].message


def test_duplicate_label() -> None:
    found = check("*A\nHLT\n*a\n")
    assert [(d.line, d.rule, d.code) for d in found] == [(3, "duplicate-label", "L4440")]


def test_on_goto_target_limit() -> None:
    text = "*A\nON M1 GOTO " + ", ".join(["*A"] * 33) + "\n"
    assert rules(text) == [(2, "too-many-targets"), (2, "line-too-long")] or rules(text) == [
        (2, "line-too-long"),
        (2, "too-many-targets"),
    ]


# ------------------------------------------------------------------------------ limits


def test_line_length_limit_excludes_the_terminator() -> None:
    ok = "M1 = 1 '" + "x" * 119
    assert len(ok) == 127
    assert rules(ok + "\r\n") == []
    found = check(ok + "1\r\n")
    assert [(d.rule, d.code, d.column, d.end_column) for d in found] == [
        ("line-too-long", "L4210", 128, 129)
    ]


def test_name_and_label_length() -> None:
    assert rules("MABCDEFGH = 1\nM = MABCDEFGH\n") == [(1, "name-too-long")]
    assert rules("*ABCDEFGHI\n") == [(1, "label-too-long")]
    assert rules("MABCDEFG = 1\n*ABCDEFGH\n") == []


def test_numbering_rules() -> None:
    assert rules("10 MOV P1\nMOV P2\n", ("P1", "P2")) == [(2, "missing-line-number")]
    assert rules("10 HLT\n\n20 HLT\n") == []  # blank lines are fine
    assert rules("10 HLT\n10 HLT\n") == [(2, "duplicate-line-number")]
    assert rules("20 HLT\n10 HLT\n") == [(2, "line-number-order")]
    found = check("0 HLT\n40000 HLT\n")
    assert [(d.line, d.rule, d.code) for d in found] == [
        (1, "line-number-range", "L4420"),
        (2, "line-number-range", "L4420"),
    ]


@pytest.mark.parametrize(
    ("text", "rule"),
    [
        ("OVRD 0", "value-out-of-range"),
        ("OVRD 101", "value-out-of-range"),
        ("HOPEN 9", "value-out-of-range"),
        ("ERROR 100", "value-out-of-range"),
    ],
)
def test_value_ranges(text: str, rule: str) -> None:
    assert rules(text) == [(1, rule)]


# ------------------------------------------------------------------------------- types


@pytest.mark.parametrize(
    "text",
    [
        "M2 = M1 * P1",
        "M2 = 2 * P_CURR",
        'M1 = "abc"',
        "C1$ = 5",
        "P3 = 5",
        'P3 = "x"',
        "P3 = J_CURR",
        "M1 = P_CURR",
    ],
)
def test_certain_type_mistakes(text: str) -> None:
    found = [d for d in check(text, ["P1"]) if d.rule == "type-mismatch"]
    assert len(found) == 1
    assert found[0].code == "L4390"


@pytest.mark.parametrize(
    "text",
    [
        "P2 = P_CURR * M1",
        "M2 = P_CURR.X * 2",
        "P2 = P_CURR * (0,0,-50,0,0,0)",
        "X = Y * Z",
        "M1 = LEN(C1$)",
        'C1$ = STR$(M1) + "x"',
        "J2 = J_CURR",
        "P2 = (PLT 1, 3)",
    ],
)
def test_allowed_type_combinations(text: str) -> None:
    assert [d for d in check(text) if d.rule == "type-mismatch"] == []


def test_definitions_silence_undefined_points() -> None:
    text = (
        "DEF POS PA\nDEF JNT JB\nP1 = P_CURR\nFOR PX = 1 TO 2\nNEXT\nINPUT #1, PIN\nDIM PT(3)\n"
        "MOV PA\nMOV JB\nMOV P1\nMOV PIN\nMOV PT(1)\nMOV P_CURR\nMOV J_CURR\nMOV PZ\n"
    )
    assert rules(text) == [(15, "undefined-point")]


# ------------------------------------------------------------------------- robustness


@pytest.mark.parametrize(
    "text",
    [
        "",
        "\n\n\n",
        "\x00\x00MOV\x00",
        bytes(range(256)).decode("latin-1"),
        "MOV P1\tTYPE\t1,0\n",
        "Ã©Ã¨ MOV PÃ©\n",
        "M1 = " + "1+" * 5000 + "1",
        "M1 = " + "(" * 300 + "1" + ")" * 300,
        "x" * 10_000,
        "IF " * 2000,
        "10 " + "9" * 5000,
    ],
)
def test_never_raises_and_stays_inside_the_file(text: str) -> None:
    found = check(text)
    assert all(isinstance(d, Diagnostic) for d in found)
    assert all(d.rule != "internal-error" for d in found)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    for d in found:
        assert 1 <= d.line <= len(lines)
        assert 1 <= d.column <= len(lines[d.line - 1]) + 1
        assert d.end_line == d.line and d.end_column <= len(lines[d.line - 1]) + 1


def test_sorted_by_position() -> None:
    found = check("HOPEN\nNEXT\nMOV (\nGOTO *X\n")
    assert [(d.line, d.column) for d in found] == sorted((d.line, d.column) for d in found)
