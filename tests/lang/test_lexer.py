"""Lexer: positions, word classes, literals, labels, operators, losslessness."""

from __future__ import annotations

import pytest

from melfa.lang import TokenKind, tokenize, untokenize

K = TokenKind


def kinds(text: str) -> list[tuple[str, str]]:
    return [(t.kind.name, t.text) for t in tokenize(text) if t.kind not in (K.NEWLINE, K.EOF)]


def test_positions_are_one_based_and_end_exclusive() -> None:
    toks = tokenize("10 MOV P1\n  HOPEN 1")
    assert [(t.text, t.line, t.column, t.end_column) for t in toks] == [
        ("10", 1, 1, 3),
        ("MOV", 1, 4, 7),
        ("P1", 1, 8, 10),
        ("\n", 1, 10, 1),
        ("HOPEN", 2, 3, 8),
        ("1", 2, 9, 10),
        ("", 2, 10, 10),
    ]
    assert toks[4].prefix == "  "
    assert toks[-1].kind is K.EOF


@pytest.mark.parametrize("word", ["mov", "Mov", "MOV", "mOv"])
def test_keywords_are_case_insensitive(word: str) -> None:
    assert tokenize(word)[0].kind is K.KEYWORD


def test_functions_are_keywords_and_system_variables_identifiers() -> None:
    assert kinds("SIN LEFT$ P_CURR M_IN C1$ COUNT%") == [
        ("KEYWORD", "SIN"),
        ("KEYWORD", "LEFT$"),
        ("IDENT", "P_CURR"),
        ("IDENT", "M_IN"),
        ("IDENT", "C1$"),
        ("IDENT", "COUNT%"),
    ]


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("42", "INTEGER"),
        ("0.5", "REAL"),
        ("50.", "REAL"),
        (".5", "REAL"),
        ("1.5E+3", "REAL"),
        ("&H0F", "HEX"),
        ("&hff", "HEX"),
        ("&B1011", "BIN"),
        ('"COM1:"', "STRING"),
        ('"', "ERROR"),
        ("@", "ERROR"),
        ("&", "ERROR"),
    ],
)
def test_literals(text: str, kind: str) -> None:
    assert kinds("M1=" + text)[2] == (kind, text)


def test_line_number_only_at_line_start() -> None:
    assert kinds("10 GOTO 20\n20 END") == [
        ("LINE_NUMBER", "10"),
        ("KEYWORD", "GOTO"),
        ("INTEGER", "20"),
        ("LINE_NUMBER", "20"),
        ("KEYWORD", "END"),
    ]


def test_label_versus_multiplication() -> None:
    assert kinds("*LOOP") == [("LABEL", "*LOOP")]
    assert kinds("10 *LOOP") == [("LINE_NUMBER", "10"), ("LABEL", "*LOOP")]
    assert kinds("GOTO *A") == [("KEYWORD", "GOTO"), ("LABEL", "*A")]
    assert kinds("ON M1 GOTO *A,*B")[-3:] == [("LABEL", "*A"), ("COMMA", ","), ("LABEL", "*B")]
    assert kinds("MOV P1*P2") == [
        ("KEYWORD", "MOV"),
        ("IDENT", "P1"),
        ("OP", "*"),
        ("IDENT", "P2"),
    ]
    assert kinds("M=(1)*SIN(X)")[5:7] == [("OP", "*"), ("KEYWORD", "SIN")]


def test_split_label_keeps_positions() -> None:
    toks = tokenize("P1*P2")
    assert [(t.text, t.column, t.end_column) for t in toks[:3]] == [
        ("P1", 1, 3),
        ("*", 3, 4),
        ("P2", 4, 6),
    ]


@pytest.mark.parametrize(
    "op",
    ["+", "-", "*", "/", "\\", "^", "=", "<>", "><", "<", "<=", "=<", ">", ">=", "=>", "<<", ">>"],
)
def test_every_operator_is_one_token(op: str) -> None:
    assert kinds(f"M1 {op} M2")[1] == ("OP", op)


@pytest.mark.parametrize("word", ["MOD", "AND", "OR", "XOR", "NOT"])
def test_operator_words_are_keywords(word: str) -> None:
    assert kinds(f"M1 {word.lower()} M2")[1] == ("KEYWORD", word.lower())


@pytest.mark.parametrize(
    "element", ["X", "y", "Z", "A", "B", "C", "L1", "L2", "FL1", "FL2", "J1", "J8"]
)
def test_element_access(element: str) -> None:
    assert kinds(f"P1.{element}") == [("IDENT", "P1"), ("DOT_ELEMENT", "." + element)]


def test_position_constant_with_omitted_elements() -> None:
    assert [k for k, _ in kinds("(X,Y,Z,,,C)(,)")] == [
        "LPAREN", "IDENT", "COMMA", "IDENT", "COMMA", "IDENT", "COMMA", "COMMA", "COMMA",
        "IDENT", "RPAREN", "LPAREN", "COMMA", "RPAREN",
    ]  # fmt: skip


def test_comments() -> None:
    assert kinds("MOV P1 ' go there") == [
        ("KEYWORD", "MOV"),
        ("IDENT", "P1"),
        ("COMMENT", "' go there"),
    ]
    assert kinds("rem anything: here") == [("COMMENT", "rem anything: here")]
    assert kinds("REMAIN = 1")[0] == ("IDENT", "REMAIN")


@pytest.mark.parametrize("newline", ["\n", "\r\n", "\r"])
def test_newlines(newline: str) -> None:
    text = f"MOV P1{newline}MOV P2{newline}"
    toks = tokenize(text)
    assert [t.line for t in toks if t.text == "MOV"] == [1, 2]
    assert [t.text for t in toks if t.kind is K.NEWLINE] == [newline, newline]
    assert untokenize(toks) == text


@pytest.mark.parametrize(
    "text",
    ["", "\t MOV\tP1  \n", "\x00\x01", "Ã©Ã¨ MOV", "a" * 10_000, "\ufeffMOV P1", '"open\n'],
)
def test_round_trip_and_no_crash(text: str) -> None:
    assert untokenize(tokenize(text)) == text


def test_unknown_characters_are_error_tokens() -> None:
    toks = tokenize("MOV P1 ? é")
    assert [(t.kind, t.text) for t in toks if t.kind is K.ERROR] == [(K.ERROR, "?"), (K.ERROR, "é")]
