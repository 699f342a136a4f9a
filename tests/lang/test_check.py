"""check(): static analysis findings, limits, numbering, types and robustness."""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.lang import Diagnostic, Severity, check
from melfa.lang.numbering import number_lines, strip_numbers
from melfa.lang.project import check_project


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
    assert found[0].message == "Position Pb is not defined"  # short, spelled as written
    assert found[0].suggestion == "Add Pb to the points file, or assign it before use (Pb = …)."


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


def test_a_mistyped_label_says_did_you_mean_as_a_mistyped_point_does() -> None:
    (found,) = check("GOTO *LOPO\n*LOOP\nEND\n")
    assert found.message == "Label *LOPO is not defined in this program. Did you mean *LOOP?"
    (far,) = check("GOTO *XYZZY\n*LOOP\nEND\n")
    assert far.message == "Label *XYZZY is not defined in this program"


def test_wihle_suggests_while_without_structure_cascade() -> None:
    found = check("WIHLE A < B\nWEND\n")
    assert [d.message for d in found] == ["WIHLE is not a MELFA BASIC IV word: did you mean WHILE?"]
    # The headline asks, the fix acts: they do not say the same sentence twice.
    assert [d.suggestion for d in found] == ["Replace with WHILE."]


def test_def_int_is_an_error_on_its_line() -> None:
    found = check("DEF DOUBLE oPx\nDEF INT npesa\nDEF POS Ppila\n")
    assert [(d.line, d.suggestion) for d in found] == [(2, "Replace with INTE.")]


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


# ------------------------------------------------------- step numbers: the two forms


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        # Editor form (some lines unnumbered): numbered lines are fine, jumps must resolve.
        ("MOV P1\n120 HLT\nGOTO 120\n", []),
        ("10 MOV P1\nMOV P2\n", []),
        ("MOV P1\n120 HLT\nGOTO 130\n", [(3, "undefined-line", Severity.ERROR)]),
        ("20 HLT\nMOV P1\n10 HLT\n", [(3, "line-number-order", Severity.ERROR)]),
        ("20 HLT\n' unnumbered\n10 HLT\n", [(3, "line-number-order", Severity.ERROR)]),
        ("10 HLT\nHLT\n10 HLT\n", [(3, "duplicate-line-number", Severity.ERROR)]),
        ("40000 HLT\nHLT\n", [(1, "line-number-range", Severity.ERROR)]),
        # Controller form (every non-blank line numbered): the controller sorts the steps.
        ("20 HLT\n10 HLT\n", [(2, "line-number-order", Severity.WARNING)]),
        ("10 HLT\n\n20 GOTO 10\n", []),
        # No numbers at all: a numeric jump cannot land anywhere.
        ("HLT\nGOTO 10\n", [(2, "undefined-line", Severity.ERROR)]),
    ],
)  # fmt: skip
def test_numbering_forms(text: str, expected: list[tuple[int, str, Severity]]) -> None:
    assert [(d.line, d.rule, d.severity) for d in check(text, ["P1", "P2"])] == expected


def test_editor_form_order_error_says_why() -> None:
    [d] = check("20 HLT\nHLT\n10 HLT\n")
    assert "upload" in d.message
    assert d.suggestion is not None and "*label" in d.suggestion


_STATEMENTS = ["MOV P1", "HOPEN 1", "M1 = M1 + 1", "DLY 0.5", "OVRD 50", "' note", "MVS P1, -50"]


@st.composite
def numbered_program(draw: st.DrawFn) -> str:
    """A valid program numbered on every line, with jumps to step numbers."""
    count = draw(st.integers(1, 12))
    numbers = sorted(draw(st.sets(st.integers(1, 32767), min_size=count, max_size=count)))
    lines = []
    for number in numbers:
        target = draw(st.sampled_from(numbers))
        other = draw(st.sampled_from(numbers))
        text = draw(
            st.sampled_from(
                [
                    *_STATEMENTS,
                    f"GOTO {target}",
                    f"GOSUB {target}",
                    f"IF M1 > 3 THEN {target}",
                    f"IF M1 > 3 THEN {target} ELSE {other}",
                    f"IF M1 > 3 THEN GOTO {target}",
                    f"ON M1 GOTO {target}, {other}",
                    f"DEF ACT 1, M_IN(1) = 1 GOSUB {target}",
                ]
            )
        )
        lines.append(f"{number} {text}")
    return "\n".join(lines) + draw(st.sampled_from(["", "\n", "\r\n"]))


@settings(max_examples=60, deadline=None)
@given(numbered_program())
def test_stripped_programs_have_no_errors(program: str) -> None:
    assert [d for d in check(program, ["P1"]) if d.is_error] == []
    stripped = strip_numbers(program)
    assert [d for d in check(stripped, ["P1"]) if d.is_error] == []
    assert [d for d in check(number_lines(stripped), ["P1"]) if d.is_error] == []


def test_strip_keeps_a_jump_target_and_check_accepts_it() -> None:
    stripped = strip_numbers("10 MOV P1\n20 HLT\n30 GOTO 20\n")
    assert stripped == "MOV P1\n20 HLT\nGOTO 20\n"
    assert check(stripped, ["P1"]) == []


# ---------------------------------------------------------------- names as written


def test_messages_spell_names_as_written() -> None:
    [d] = check("MOV Pa\n", ["Pb"])
    assert d.message == "Position Pa is not defined"
    assert "Pa" in (d.suggestion or "") and "PA" not in (d.suggestion or "")
    [d] = check("MCounter12 = 0\n")
    assert d.message.startswith("Name MCounter12 is longer than 8 characters")
    [d] = check("M1 = 1\nCmsg$ = 5\n")
    assert d.message.endswith("the string variable Cmsg$")
    [d] = check("GOTO *myLabel\n")
    assert d.message == "Label *myLabel is not defined in this program"
    found = check("*LongLabel1\n*longlabel1\n")
    assert [d.message for d in found if d.rule == "duplicate-label"] == [
        "Label *longlabel1 is already defined on line 1"
    ]
    [d] = check("FOR Mi = 1 TO 2\nNEXT Mj\n")
    assert d.message == "NEXT Mj does not match FOR Mi (line 1)"
    assert d.suggestion == "Write NEXT Mi."


def test_the_tree_keeps_upper_case_names_and_the_spelling() -> None:
    from melfa.lang import ast as A  # noqa: N812
    from melfa.lang import parse

    stmt = parse("MOV pGoal\n").lines[0].statement
    assert isinstance(stmt, A.Move) and isinstance(stmt.target, A.Name)
    assert (stmt.target.name, stmt.target.text, stmt.target.written) == ("PGOAL", "pGoal", "pGoal")
    assert stmt.target == A.Name("PGOAL", stmt.target.span)  # the spelling is not identity
    line = parse("*Loop\n").lines[0]
    assert (line.label, line.label_text) == ("LOOP", "Loop")


# ------------------------------------------------------------------------- suggestions

# Rules whose every finding has a clear fix, so it must come with a suggestion.
NO_GENERAL_FIX = {
    "syntax-error",
    "invalid-statement",
    "unknown-statement",
    "expected-expression",
    "internal-error",
}
BROKEN = [
    "WIHLE M1 < 3\nWEND",
    "GOTO *mylabel\nmylabel",
    "IF A < B HOPEN 1",
    "IF A < B M1 = 2",
    "IF end < start THEN HOPEN",
    "DEF INT npesa",
    "DEF QQQ X",
    "DEF IO MS = BTI, 900",
    "DEF PLT 1, P1, P2",
    "MOV",
    "MVR P1, P2",
    "SPD 10, 20",
    "HLT 1",
    "M1 = ",
    "M1 = P1.Q",
    "M1 = P1.FL",
    "MOV P1 P2",
    'PRINT #1, "abc',
    "M1 = 3 @ 4",
    "_COUNT = 1",
    "M1 = END",
    "INT = 3",
    "FOR END = 1 TO 3\nNEXT",
    "FOR M1 = 1 10\nNEXT",
    "M1 = SIN(3",
    "SERVO",
    "CMP X",
    "ON M1 *A",
    "IF THEN *A",
    "WAIT",
    "WHILE\nWEND",
    "SELECT\nEND SELECT",
    "SELECT M1\nCASE\nEND SELECT",
    "SELECT M1\nCASE IS 3\nEND SELECT",
    "END IF",
    "DEF ACT 1, M1 = 1 *A",
    "DIM MA()",
    'OPEN "COM1:" FOR READ AS #1',
    "COM(1) GO",
    "IF M1 THEN *A ELSE",
    "M1 = ()",
    "HOPEN 1 *A",
    "NEXT\nWEND\nENDIF\nELSE\nEND SELECT\nCASE 1\nBREAK",
    "FOR M1 = 1 TO 2\nWHILE M2\nSELECT M3\nIF M4 THEN",
    "IF M1 THEN\nELSE\nELSE\nENDIF",
    "SELECT M1\nCASE 1\nSELECT M2\nEND SELECT\nEND SELECT",
    "".join(f"FOR M{i} = 1 TO 2\n" for i in range(17)) + "NEXT\n" * 17,
    "IF M1 THEN\n" * 9 + "ENDIF\n" * 9,
    "*A\nON M1 GOTO " + ",".join(["*A"] * 33),
    "GOTO *LOPP\n*LOOP",
    "GOTO 10",
    "*A\n*a\n*ABCDEFGHI",
    "MABCDEFGH = 1",
    "M1 = 2 * P1\nM2 = 2 / P1",
    'M1 = "x"\nC1$ = 1\nP1 = J1\nP2 = 5',
    "20 HLT\n10 HLT\n10 HLT\n0 HLT",
    "M1 = 1 '" + "x" * 130,
    "OVRD 0\nJOVRD 101\nHOPEN 9\nHCLOSE -1\nERROR 100\nDLY 0.01\nDLY -1\nM_OUT(1) = 1 DLY 0",
    "DEF PLT 9, P1, P2, P3, , 3, 3, 1\nMOV (PLT 0, 1)",
    "DEF POS " + ", ".join(f"P{i}" for i in range(40)),
    "DIM MA(1, 2, 3, 4)\nDIM MB(0)\nDIM MC(1000)\nDIM MD(M1)\nDIM ME(2.5)",
    "MOV PX",
    "FOR M1 = 1 TO 3\nNEXT M2",
    "THEN M1 = 1",
]


def _all_findings() -> list[Diagnostic]:
    return [d for text in BROKEN for d in check(text)]


def test_every_suggestion_is_a_short_imperative_sentence() -> None:
    found = [d for d in _all_findings() if d.suggestion is not None]
    assert len(found) > 60
    for d in found:
        s = d.suggestion or ""
        assert re.fullmatch(r"[A-Z][a-z]+ .*[.…]", s), (d.rule, s)
        assert len(s) <= 100, (d.rule, s)


def test_every_finding_with_a_clear_fix_has_a_suggestion() -> None:
    found = _all_findings()
    missing = [
        (d.rule, d.message) for d in found if d.rule not in NO_GENERAL_FIX and not d.suggestion
    ]
    assert missing == []
    rules = {d.rule for d in found}
    assert len(rules) >= 45  # the corpus reaches most rules


@pytest.mark.parametrize(
    ("text", "suggestion"),
    [
        ("WIHLE M1 < 3\nWEND\n", "Replace with WHILE."),
        ("GOTO *mylabel\nmylabel\n", "Write *mylabel to define the label."),
        ("IF A < B HOPEN 1\n", "Add THEN after the condition: IF A < B THEN HOPEN …"),
        ("IF A < B\n", "Add THEN after the condition: IF A < B THEN …"),
        ("HOPEN\n", "Add a hand number (1 to 8) after HOPEN, e.g. HOPEN 1."),
        ("GOTO *LOPP\n*LOOP\n", "Write *LOOP instead of *LOPP, or define *LOPP."),
        ("M1 = 2 * P1\n", "Put the position first: P1 * 2."),
        ("M1 = P1.FL\n", "Write .FL1 instead of .FL."),
        ("FOR M1 = 1 10\nNEXT\n", "Write TO after the FOR start value."),
    ],
)
def test_suggestions_say_what_to_write(text: str, suggestion: str) -> None:
    assert suggestion in [d.suggestion for d in check(text, ["P1"])]


def test_undefined_point_keeps_its_message_short() -> None:
    [d] = check("MOV P9\n")
    assert d.message == "Position P9 is not defined"
    assert d.suggestion == "Add P9 to the points file, or assign it before use (P9 = …)."


# ----------------------------------------------------------------- limits of §3, §4.6


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("OVRD 100\nOVRD 1\nJOVRD 50\nHOPEN 8\nHCLOSE 1\nERROR 9299\nDLY 0.05\n", []),
        ("OVRD -5", [(1, "value-out-of-range", Severity.ERROR)]),
        ("HCLOSE 9", [(1, "value-out-of-range", Severity.ERROR)]),
        ("ERROR 9300", [(1, "value-out-of-range", Severity.ERROR)]),
        ("OVRD M1\nHOPEN M2\nDLY M3\n", []),  # not constants: not checked
        ("DLY 0.01", [(1, "value-out-of-range", Severity.WARNING)]),
        ("DLY 0", [(1, "value-out-of-range", Severity.WARNING)]),
        ("DLY -1", [(1, "value-out-of-range", Severity.ERROR)]),
        ("M_OUT(17) = 1 DLY 0.01", [(1, "value-out-of-range", Severity.WARNING)]),
        ("M_OUT(17) = 1 DLY 0.5", []),
        ("DEF PLT 1, P1, P2, P3, , 3, 3, 1\nMOV (PLT 1, 5)\nMOV (PLT 8, 1)", []),
        ("DEF PLT 9, P1, P2, P3, , 3, 3, 1", [(1, "value-out-of-range", Severity.ERROR)]),
        ("MOV (PLT 0, 5)", [(1, "value-out-of-range", Severity.ERROR)]),
        ("DIM MA(999), MB(1, 2, 3)", []),
        ("DIM MA(1, 2, 3, 4)", [(1, "dim-dimensions", Severity.ERROR)]),
        ("DIM MA(0)", [(1, "dim-size", Severity.ERROR)]),
        ("DIM MA(1000)", [(1, "dim-size", Severity.ERROR)]),
        ("DIM MA(M1)", [(1, "dim-size", Severity.ERROR)]),
        ("DIM MA(2.5)", [(1, "dim-size", Severity.ERROR)]),
        ("_COUNT = 1", [(1, "name-starts-with-underscore", Severity.ERROR)]),
        ("M_COUNT = 1\nMA_B = 2", []),
    ],
)  # fmt: skip
def test_limits(text: str, expected: list[tuple[int, str, Severity]]) -> None:
    found = check(text, ["P1", "P2", "P3"])
    assert [(d.line, d.rule, d.severity) for d in found] == expected


def test_value_out_of_range_points_at_the_value() -> None:
    [d] = check("OVRD 150\n")
    assert (d.column, d.end_column) == (6, 9)
    assert d.message == "OVRD takes more than 0 and up to 100 (%), found 150"
    assert d.suggestion == "Use a value above 0 and up to 100."


def test_def_list_length() -> None:
    head = "DEF INTE " + "".join(f"M{i:03d}, " for i in range(18))  # 117 characters
    fits, long = head + "MLAST1", head + "MLAST12"
    assert (len(fits), len(long)) == (123, 124)
    assert rules(fits) == []
    [d] = check(long)
    assert (d.rule, d.column, d.end_column) == ("def-too-long", 124, 125)
    assert d.suggestion == "Split the names over two DEF INTE lines."
    assert check("10 " + long)[0].column == 127  # counted from DEF, not from the step number
    assert rules("10 " + fits) == []


def test_underscore_message() -> None:
    [d] = check("_COUNT = 1\n")
    assert (d.code, d.column, d.end_column) == ("L4310", 1, 2)
    assert d.message == "A name cannot start with '_' (_COUNT)"
    assert d.suggestion == "Start the name with a letter, e.g. MCOUNT; '_' may come later."


@pytest.mark.parametrize(
    ("text", "suggestion"),
    [
        ("MOV M1", "Move to a position variable or constant, e.g. MOV P1."),
        ('MVS "x"', "Move to a position variable or constant, e.g. MVS P1."),
        ("MVS P1.Z", "Change the element in a copy of the position and move to the copy."),
        ("MVR P1, 5, P2", "Use positions, e.g. MVR P1, P2, P3."),
    ],
)
def test_move_to_a_number_is_a_type_mismatch(text: str, suggestion: str) -> None:
    [d] = check(text, ["P1", "P2"])
    assert (d.rule, d.code, d.suggestion) == ("type-mismatch", "L4390", suggestion)


@pytest.mark.parametrize(
    "text", ["MOV P1\nMOV J1\nMOV (PLT 1, 2)\nMOV P1 * M1\nMOV (1,2,3,4,5,6)\nMOV P_CURR\n"]
)
def test_moves_to_positions_are_fine(text: str) -> None:
    assert check(text, ["P1", "J1"]) == []


def test_a_broken_end_if_does_not_hide_an_unclosed_select() -> None:
    found = rules("SELECT M1\nCASE 1\nIF M1 THEN\nEND IF\n")
    assert found == [(1, "select-without-end"), (4, "unknown-statement")]


def test_an_undefined_point_is_reported_once() -> None:
    found = check("MOV Pa\nMVS Pa, -50\nMOV Pb\nMOV Pa\n")
    assert [(d.line, d.message) for d in found] == [
        (1, "Position Pa is not defined"),
        (3, "Position Pb is not defined"),
    ]


@pytest.mark.parametrize(
    ("text", "message", "suggestion"),
    [
        ("IF M1 = THEN *A\n*A", "Expected a value before THEN", "Write a value after =."),
        ("IF M1 THEN M2 = ELSE M2 = 3", "Expected a value before ELSE", "Write a value after =."),
        ("FOR M1 = TO 3\nNEXT", "Expected a value before TO", "Write a value after =."),
        ("M1 = 1 + * 2", "Expected a value, found *",
         "Write a number, a variable or an expression after +."),
    ],
)  # fmt: skip
def test_a_missing_value_is_not_a_reserved_word(text: str, message: str, suggestion: str) -> None:
    [d] = check(text)
    assert (d.rule, d.message, d.suggestion) == ("expected-expression", message, suggestion)


PHOM = "MOV Phom\nMOV Pzz\nMOV Phomf\nEND\n"


def test_a_misspelt_point_gets_did_you_mean_before_add_it() -> None:
    """``Phom`` with ``Phome`` defined: the close name first (one click writes it), never
    only "add Phom" (which would make a bogus point where the arm stands)."""
    found = [
        d
        for d in check_project([PHOM], ["Phome=(300,0,400,180,0,180)(7,0)\n"]).programs[0]
        if d.rule == "undefined-point"
    ]
    typo, other, far = found
    assert typo.message == "Position Phom is not defined. Did you mean Phome?"
    assert typo.replace == "Phome"
    assert typo.suggestion is not None and typo.suggestion.startswith("Write Phome instead")
    assert typo.to_json()["replace"] == "Phome"
    assert other.replace is None and other.to_json()["replace"] is None  # short: no guess
    assert far.replace == "Phome"
