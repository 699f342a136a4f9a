"""Parser: every statement form, expression precedence, and the shape of error recovery."""

from __future__ import annotations

import pytest

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.parser import parse


def stmt(text: str) -> A.Statement:
    lines = parse(text).lines
    assert lines[0].issues == (), lines[0].issues
    statement = lines[0].statement
    assert statement is not None
    return statement


def issues(text: str) -> list[A.ParseIssue]:
    return [issue for line in parse(text).lines for issue in line.issues]


VALID = [
    # movement
    ("MOV P1", A.Move),
    ("MOV P1, -50", A.Move),
    ("MOV P1 TYPE 1,0", A.Move),
    ("MOV (PLT 1,10),100.0 WTH M_OUT(17)=1", A.Move),
    ("MOV P4+P5,50.0 WTHIF M_IN(18)=1,M_OUT(20)=1 DLY M1+2", A.Move),
    ("MOV P33 WTHIF M_IN(10)=0, SKIP", A.Move),
    ("MOV P1 WTH HLT", A.Move),
    ("MOV J1", A.Move),
    ("MOV P1*P2", A.Move),
    ("MOV (1,2,3,4,5,6)(7,0)", A.Move),
    ("MOV P_CURR", A.Move),
    ("MVS P1", A.Move),
    ("MVS ,-50", A.Move),
    ("MVS P1, 10 TYPE 0, 1", A.Move),
    ("MVR P1, P2, P3", A.ArcMove),
    ("MVR2 P1, P2, P3", A.ArcMove),
    ("MVR3 P1, P2, P3", A.ArcMove),
    ("MVC P1, P2, P3", A.ArcMove),
    ("MVA P1, 2", A.ArchMove),
    # speed and acceleration
    ("OVRD 50", A.Command),
    ("OVRD 50, 20, 30", A.Command),
    ("JOVRD 20", A.Command),
    ("SPD 100", A.Command),
    ("SPD M_NSPD", A.Command),
    ("ACCEL", A.Command),
    ("ACCEL 50, 60", A.Command),
    ("ACCEL ,60", A.Command),
    ("CNT 1, 100, 200", A.Command),
    ("CNT 0", A.Command),
    ("FINE 300, 1", A.Command),
    ("PREC ON", A.Switch),
    ("OADL OFF", A.Switch),
    ("LOADSET 1, 1", A.Command),
    ("TORQ 4, 10", A.Command),
    ("JRC +1", A.Command),
    # hand, servo, frames
    ("HOPEN 1", A.Command),
    ("HCLOSE 2", A.Command),
    ("SERVO ON", A.Switch),
    ("SERVO OFF", A.Switch),
    ("TOOL (100,100,0,0,0,0)", A.Command),
    ("TOOL P_NTOOL", A.Command),
    ("BASE (50,100,0,0,0,0,0,0)", A.Command),
    # flow
    ("GOTO 100", A.Goto),
    ("GOTO *LOOP", A.Goto),
    ("GOSUB *SUB1", A.Gosub),
    ("ON M1 GOTO 100, *A, 300", A.OnJump),
    ("ON M1 GOSUB *A, *B", A.OnJump),
    ("RETURN", A.Return),
    ("RETURN 0", A.Return),
    ("RETURN 1", A.Return),
    ("IF M1>10 THEN 1000", A.If),
    ("IF M1<=12 THEN *LOOP", A.If),
    ("IF M1>10 THEN GOTO 1000 ELSE GOTO 2000", A.If),
    ("IF M_IN(8)=1 THEN HOPEN 1 ELSE *L", A.If),
    ("IF M1 = 1 THEN M2 = 3", A.If),
    ("IF M1 = 1 THEN", A.If),
    ("ELSE", A.Else),
    ("ENDIF", A.EndIf),
    ("FOR M1 = 1 TO 10", A.For),
    ("FOR M1 = 10 TO 1 STEP -1", A.For),
    ("NEXT", A.Next),
    ("NEXT M1", A.Next),
    ("NEXT M2, M1", A.Next),
    ("WHILE M1 < 10", A.While),
    ("WEND", A.Wend),
    ("SELECT M1", A.Select),
    ("CASE 1", A.Case),
    ("CASE IS >= 5", A.Case),
    ("CASE 1 TO 4", A.Case),
    ("BREAK", A.Break),
    ("DEFAULT", A.Default),
    ("END SELECT", A.EndSelect),
    ("END", A.Command),
    ("HLT", A.Command),
    ("DLY 0.5", A.Command),
    ("WAIT M_IN(1)=1", A.Wait),
    ("ERROR 9100", A.Command),
    ("SKIP", A.Command),
    ('CALLP "P10", M1, P2', A.Command),
    ("FPRM M1, P2", A.Fprm),
    # definitions
    ("DEF INTE A, B", A.DefVar),
    ("DEF FLOAT F1", A.DefVar),
    ("DEF DOUBLE oPx, oPy, angle", A.DefVar),
    ("DEF CHAR MSG", A.DefVar),
    ("DEF POS Ppila", A.DefVar),
    ("DEF POS Pa=(584.73,141.04,385.25,-163.74,1.11,-78.61)(7,0)", A.DefVar),
    ("DEF JNT JSAFE", A.DefVar),
    ("DEF IO PORT1 = BIT, 900", A.DefIO),
    ("DEF IO PORT2 = BYTE, 10, &H0F", A.DefIO),
    ("DEF FNMAX(A, B) = (A + B + ABS(A - B)) / 2", A.DefFn),
    ("DEF PLT 1, P1, P2, P3, P4, 4, 3, 1", A.DefPlt),
    ("DEF PLT 1,P1,P2,P3, ,4,3,1", A.DefPlt),
    ("DEF ACT 1, M_IN(10)=1 GOSUB *L, S", A.DefAct),
    ("DEF ACT 3, M_TIMER(1)>10.5 GOSUB 300", A.DefAct),
    ("DEF ARCH 1, 10, 10, 100", A.Command),
    ("DIM PT(10), MX(3, 4)", A.Dim),
    ("ACT 1 = 1", A.ActSet),
    ("ACT 0 = 0", A.ActSet),
    # i/o and files
    ('OPEN "COM1:" AS #1', A.Open),
    ('OPEN "TEMP" FOR APPEND AS #2', A.Open),
    ('PRINT #1, "x="; M1, P1', A.Print),
    ("INPUT #1, M1, P_01.X", A.Input),
    ("CLOSE", A.Close),
    ("CLOSE #1", A.Close),
    ("ON COM(1) GOSUB *RECV", A.OnCom),
    ("ON COM GOSUB 100", A.OnCom),
    ("COM(1) ON", A.ComControl),
    ("COM STOP", A.ComControl),
    # multitask and misc
    ('XLOAD 2, "10"', A.Command),
    ("XRUN 2", A.Command),
    ("XSTP 2", A.Command),
    ("XRST 2", A.Command),
    ("XCLR 2", A.Command),
    ("PRIORITY 3", A.Command),
    ("GETM 1", A.Command),
    ("RELM 1", A.Command),
    ("CMP JNT, &B11", A.Cmp),
    ("CMP OFF", A.Cmp),
    ("CMPG 1, 1, 1, 1, 1, 1", A.Command),
    ("CLR 1", A.Command),
    ("RESET ERR", A.Command),
    ("CHRSRCH C1$, C2$, M1", A.Command),
    # assignments
    ("M1 = 5", A.Assign),
    ("P1.X = 5", A.Assign),
    ("P44.A = P_CURR.A - 0.317", A.Assign),
    ("M_OUT(17) = 1", A.Assign),
    ("M_OUT(17) = 1 DLY 0.5", A.Assign),
    ("M_TIMER(1) = 0", A.Assign),
    ("PT(3) = P1", A.Assign),
    ('C1$ = LEFT$("ABC", 2) + CHR$(65)', A.Assign),
    ("P2 = INV(P1) * P3", A.Assign),
    ("J1 = (0,10,80,10,90,0)", A.Assign),
    ("M1 = &H41FF AND &B11111111", A.Assign),
    ("M1 = ATN2(P1.Y, P1.X)", A.Assign),
    ("M1 = 10 MOD 3 + 7 \\ 2", A.Assign),
    ("M1 = M2 << 2 XOR 1", A.Assign),
    ("PNEXT = (PLT 1, M1)", A.Assign),
    ("P1 = P_CURR * (0,0,-50,0,0,0)", A.Assign),
    ("M2 = FNMAX(M1, 3)", A.Assign),
    ("M1 = DEG(J_CURR.J4)", A.Assign),
]


@pytest.mark.parametrize(("text", "node"), VALID, ids=[t for t, _ in VALID])
def test_valid_statement(text: str, node: type) -> None:
    assert type(stmt(text)) is node


@pytest.mark.parametrize(("text", "node"), VALID[::7], ids=[t for t, _ in VALID[::7]])
def test_valid_statement_lower_case_and_numbered(text: str, node: type) -> None:
    line = parse("100 " + text.lower()).lines[0]
    assert line.issues == ()
    assert line.number == 100
    assert type(line.statement) is node


INVALID = [
    ("MOV", "missing-argument"),
    ("MVR P1, P2", "missing-argument"),
    ("HOPEN", "missing-argument"),
    ("SPD 10, 20", "too-many-arguments"),
    ("OVRD", "missing-argument"),
    ("SERVO", "syntax-error"),
    ("GOTO", "syntax-error"),
    ("GOTO LOOP", "label-without-star"),
    ("ON M1 100", "syntax-error"),
    ("IF M1 > 2", "expected-then"),
    ("IF M1 > 2 M2 = 1", "expected-then"),
    ("FOR M1 = 1", "syntax-error"),
    ("FOR = 1 TO 2", "reserved-word"),
    ("NEXT 3", "syntax-error"),
    ("WHILE", "missing-argument"),
    ("SELECT", "missing-argument"),
    ("CASE IS 3", "syntax-error"),
    ("DEF INT A", "unknown-def-type"),
    ("DEF", "unknown-def-type"),
    ("DEF IO X = NIBBLE, 1", "syntax-error"),
    ("DEF PLT 1, P1, P2", "missing-argument"),
    ("DIM A", "syntax-error"),
    ("M1 = ", "expected-expression"),
    ("M1 = (1 + 2", "syntax-error"),
    ("M1 = SIN 3", "syntax-error"),
    ("P1.Q = 3", "unknown-element"),
    ("END = 3", "reserved-word"),
    ("INT = 3", "reserved-word"),
    ("THEN", "invalid-statement"),
    ("HALT", "unknown-statement"),
    ("WIHLE M1 < 2", "unknown-statement"),
    ("COUNT", "unknown-statement"),
    ("MOV P1 P2", "unexpected-token"),
    ("MOV P1 ?", "illegal-character"),
    ('M1 = "abc', "unclosed-string"),
    ("END IF", "unknown-statement"),
    ("CMP FOO", "syntax-error"),
    ("COM(1) MAYBE", "syntax-error"),
    ('OPEN "X" AS', "expected-expression"),
    ("RESET", "syntax-error"),
    ("ACT 1", "syntax-error"),
    ("1 2 3", "invalid-statement"),
]


@pytest.mark.parametrize(("text", "rule"), INVALID, ids=[t for t, _ in INVALID])
def test_invalid_statement(text: str, rule: str) -> None:
    found = issues(text)
    assert [i.rule for i in found][:1] == [rule]
    assert len(found) == 1


def test_invalid_line_becomes_invalid_statement_with_its_text() -> None:
    line = parse("MOV P1 P2 ' comment").lines[0]
    assert line.comment == " comment"
    assert isinstance(line.statement, A.Move)  # the statement was complete…
    assert line.issues[0].rule == "unexpected-token"  # …but something followed it
    broken = parse("DEF INT npesa").lines[0].statement
    assert isinstance(broken, A.InvalidStatement)
    assert broken.text == "DEF INT npesa"
    assert broken.issue.replacement == "INTE"
    assert broken.issue.suggestion == "Replace with INTE."
    assert broken.issue.span == A.Span(1, 5, 1, 8)


# ------------------------------------------------------------------------ typo suggestions


@pytest.mark.parametrize(
    ("typo", "keyword"),
    [("WIHLE", "WHILE"), ("KOSUB", "GOSUB"), ("KOSU", "GOSUB"), ("HALT", "HLT"), ("hopn", "HOPEN")],
)
def test_typo_suggestions(typo: str, keyword: str) -> None:
    (issue,) = issues(f"{typo} 1")
    assert issue.message == f"{typo} is not a MELFA BASIC IV word: did you mean {keyword}?"
    assert issue.replacement == keyword
    assert issue.suggestion == f"Replace with {keyword}."


def test_no_suggestion_when_too_different() -> None:
    (issue,) = issues("KOKUB")
    assert issue.suggestion is None
    assert "expected '='" in issue.message


def test_no_suggestion_for_an_assignment() -> None:
    assert issues("WIHLE = 3") == []


def test_def_type_suggestion() -> None:
    (issue,) = issues("DEF INT npesa")
    assert issue.message == "Unknown DEF type INT. Did you mean DEF INTE?"


def test_bare_label_needs_star() -> None:
    program = parse("GOTO *mylabel\nmylabel\n")
    assert program.lines[0].issues == ()
    (issue,) = program.lines[1].issues
    assert issue.rule == "label-without-star"
    assert issue.message.startswith("Label needs to start with *")


# -------------------------------------------------------------------------- recovery shape


def test_thesis_if_example_recovers_after_then() -> None:
    program = parse("IF a < b HOPEN\nIF end < start THEN HOPEN\n")
    first, second = program.lines[0], program.lines[1]
    assert [i.rule for i in first.issues] == ["expected-then", "missing-argument"]
    assert [i.rule for i in second.issues] == ["reserved-word", "missing-argument"]
    assert isinstance(first.statement, A.If)
    assert isinstance(first.statement.condition, A.Binary)
    assert isinstance(first.statement.then, A.InvalidStatement)
    assert isinstance(second.statement, A.If)
    assert isinstance(second.statement.condition, A.InvalidExpr)
    assert isinstance(second.statement.then, A.InvalidStatement)
    assert second.statement.then.text == "HOPEN"


def test_recovery_at_else() -> None:
    line = parse("IF M1 THEN HOPEN ELSE GOTO *X").lines[0]
    assert isinstance(line.statement, A.If)
    assert isinstance(line.statement.then, A.InvalidStatement)
    assert isinstance(line.statement.else_, A.Goto)
    assert len(line.issues) == 1


def test_one_error_per_line_without_structural_keyword() -> None:
    line = parse("MOV P1,, ? ? (").lines[0]
    assert len(line.issues) == 1
    assert isinstance(line.statement, A.InvalidStatement)


def test_broken_line_does_not_hide_the_next() -> None:
    program = parse("MOV (\nHOPEN\nMOV P1\n")
    assert [len(line.issues) for line in program.lines] == [1, 1, 0, 0]
    assert isinstance(program.lines[2].statement, A.Move)


# ---------------------------------------------------------------------------- expressions


def value(text: str) -> A.Expr:
    statement = stmt("M = " + text)
    assert isinstance(statement, A.Assign)
    return statement.value


def shape(expr: A.Expr | None) -> object:
    """A compact view of an expression tree for comparisons."""
    if isinstance(expr, A.Binary):
        return (expr.op.value, shape(expr.left), shape(expr.right))
    if isinstance(expr, A.Unary):
        return (expr.op.value, shape(expr.operand))
    if isinstance(expr, A.Number):
        return expr.value
    if isinstance(expr, A.Name):
        return expr.name
    return type(expr).__name__


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("1 + 2 * 3", ("+", 1, ("*", 2, 3))),
        ("-2 ^ 2", ("-", ("^", 2, 2))),
        ("-A * B", ("*", ("-", "A"), "B")),
        ("A * B \\ C", ("\\", ("*", "A", "B"), "C")),
        ("A \\ B MOD C", ("MOD", ("\\", "A", "B"), "C")),
        ("A MOD B + C", ("+", ("MOD", "A", "B"), "C")),
        ("A + B << C", ("<<", ("+", "A", "B"), "C")),
        ("A << B = C", ("=", ("<<", "A", "B"), "C")),
        ("NOT A = B", ("NOT", ("=", "A", "B"))),
        ("NOT A AND B", ("AND", ("NOT", "A"), "B")),
        ("A AND B OR C", ("OR", ("AND", "A", "B"), "C")),
        ("A OR B XOR C", ("XOR", ("OR", "A", "B"), "C")),
        ("A - B - C", ("-", ("-", "A", "B"), "C")),
        ("(A + B) * C", ("*", ("+", "A", "B"), "C")),
        ("A >< B", ("<>", "A", "B")),
        ("A =< B", ("<=", "A", "B")),
        ("A => B", (">=", "A", "B")),
    ],
)
def test_precedence_follows_the_reference_table(text: str, expected: object) -> None:
    assert shape(value(text)) == expected


def test_position_literal_with_omitted_elements_and_flags() -> None:
    lit = value("(1,2,3,,,6)(7,0)")
    assert isinstance(lit, A.PositionLiteral)
    assert [shape(e) if e else None for e in lit.elements] == [1, 2, 3, None, None, 6]
    assert lit.flags is not None and [shape(e) for e in lit.flags if e] == [7, 0]
    empty = value("(,)")
    assert isinstance(empty, A.PositionLiteral)
    assert empty.elements == (None, None) and empty.flags is None


def test_hex_bin_and_real_values() -> None:
    assert shape(value("&H0F + &B11 + 0.5")) == ("+", ("+", 15, 3), 0.5)


def test_element_index_call_and_pallet_nodes() -> None:
    assert isinstance(value("P1.FL1"), A.Element)
    index = value("M_IN(3)")
    assert isinstance(index, A.Index) and index.name.name == "M_IN"
    call = value("MID$(C$, 1, 2)")
    assert isinstance(call, A.Call) and not call.user and len(call.args) == 3
    assert isinstance(value("FNX(1)"), A.Call)
    pallet = value("(PLT 1, 5)")
    assert isinstance(pallet, A.Pallet)


def test_move_details() -> None:
    move = stmt("MOV P4+P5,50.0 TYPE 1,0 WTHIF M_IN(18)=1,M_OUT(20)=1 DLY M1+2")
    assert isinstance(move, A.Move)
    assert shape(move.target) == ("+", "P4", "P5")
    assert shape(move.close) == 50.0
    assert move.type is not None and shape(move.type.c1) == 1
    assert move.appended is not None and move.appended.condition is not None
    action = move.appended.action
    assert isinstance(action, A.Assign) and shape(action.pulse) == ("+", "M1", 2)
    mvs = stmt("MVS , -50")
    assert isinstance(mvs, A.Move) and mvs.target is None and shape(mvs.close) == ("-", 50)


def test_if_branches_are_targets_or_statements() -> None:
    statement = stmt("IF M1>10 THEN 1000 ELSE *L2")
    assert isinstance(statement, A.If)
    assert statement.then == A.LineRef(1000, A.Span(1, 15, 1, 19))
    assert isinstance(statement.else_, A.LabelRef) and statement.else_.name == "L2"
    assert stmt("IF M1 THEN").is_block  # type: ignore[union-attr]


def test_case_forms() -> None:
    case = stmt("CASE IS <> 3")
    assert isinstance(case, A.Case) and case.kind is A.CaseKind.IS and case.op is A.BinaryOp.NE
    rng = stmt("CASE 1 TO 5")
    assert isinstance(rng, A.Case) and rng.kind is A.CaseKind.RANGE and shape(rng.high) == 5


def test_line_fields() -> None:
    program = parse("10 *LOOP ' start\n20 MOV P1\n\n")
    first = program.lines[0]
    assert (first.number, first.label, first.statement, first.comment) == (
        10,
        "LOOP",
        None,
        " start",
    )
    assert first.label_span == A.Span(1, 4, 1, 9)
    assert len(program.lines) == 4  # one per text line, the empty last one included
    assert program.lines[1].span == A.Span(2, 1, 2, 10)


def test_thesis_programs_parse_cleanly() -> None:
    sample = "10 SERVO ON\n20 SPD 20\n30 OVRD 20\n40 MOV Pa\n50 MOV Pb\n60 HOPEN 1\n70 END\n"
    assert parse(sample).issues == ()
    pyramid = (
        "10 DEF DOUBLE oPx, oPy, angle, cPx, cPy, alt, radi, diam 'Punts carac\n"
        "20 DEF INTE npesa\n30 DEF POS Ppila\n40 DEF POS Pi, Po 'Punts entrada\n"
        "50 'Definir punts inicials\n60 'Centre de la piràmide\n70 oPx=16.4\n80 oPy=550.0\n"
        "90 'Posició de la pila de peçes\n100 Ppila = PCOLOC\n110     radi=27\n120 diam=54\n"
        "130 'Posició de la c#mara\n140 cPx=0 + 2*diam\n150 cPy=0 + diam\n"
    )
    assert parse(pyramid).issues == ()
