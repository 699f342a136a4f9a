"""Token kinds and the word lists of MELFA BASIC IV.

A `Token` keeps the whitespace before it (`prefix`), so the text is rebuilt exactly with
``"".join(t.prefix + t.text for t in tokens)``; `melfa fmt` and renumbering rely on it.
Lines and columns are 1-based and the end is exclusive (the convention of
`melfa.lang.diagnostics`). Words are case-insensitive: compare ``text.upper()``.
"""

from __future__ import annotations

import enum
from typing import NamedTuple

from melfa.lang import model as _model


class TokenKind(enum.Enum):
    """What a token is. Keywords and identifiers are told apart by the word lists below."""

    LINE_NUMBER = "line_number"  # a step number leading a line: `10 MOV P1`
    KEYWORD = "keyword"  # statement words, operator words, built-in function names
    IDENT = "ident"  # variable names, including system variables (`P_CURR`, `M_IN`)
    LABEL = "label"  # `*NAME` (a jump target or a label definition)
    INTEGER = "integer"
    REAL = "real"
    HEX = "hex"  # `&H0F`
    BIN = "bin"  # `&B1011`
    STRING = "string"  # `"text"` including the quotes
    OP = "op"  # + - * / \ ^ = <> >< < <= =< > >= => << >> # ;
    COMMA = "comma"
    LPAREN = "lparen"
    RPAREN = "rparen"
    DOT_ELEMENT = "dot_element"  # `.X`, `.FL1`, `.J3`
    COMMENT = "comment"  # `' text` or `REM text` (to the end of the line)
    NEWLINE = "newline"  # CRLF, CR or LF, kept as written
    EOF = "eof"
    ERROR = "error"  # a character the language does not have, or an unterminated string

    # Enum's own __hash__ runs Python code; members are singletons, so identity hashing is
    # equivalent and keeps `kind in {...}` cheap in the lexer and parser hot loops.
    __hash__ = object.__hash__


class Token(NamedTuple):
    """One token with its position (1-based, end exclusive) and the whitespace before it."""

    kind: TokenKind
    text: str
    line: int
    column: int
    end_line: int
    end_column: int
    prefix: str


#: Words that can start a statement; the typo checker suggests only these. The statement
#: words, like the functions below, are the language model's (`melfa.lang.model`).
STATEMENT_KEYWORDS: frozenset[str] = _model.STATEMENTS

#: Words that only appear inside statements.
SECONDARY_KEYWORDS: frozenset[str] = _model.SECONDARY_WORDS

#: Built-in functions (COSIMIR list plus SETJNT/SETPOS); lexed as keywords. Their arities and
#: argument kinds are in `melfa.lang.model.FUNCTIONS`, the one home of that knowledge.
FUNCTIONS: frozenset[str] = frozenset(_model.FUNCTIONS)

#: Every reserved word (a KEYWORD token).
KEYWORDS: frozenset[str] = STATEMENT_KEYWORDS | SECONDARY_KEYWORDS | FUNCTIONS

#: Components after a dot, in upper case.
ELEMENTS: frozenset[str] = frozenset(
    "X Y Z A B C L1 L2 FL1 FL2 J1 J2 J3 J4 J5 J6 J7 J8".split()  # noqa: SIM905
)

#: Comparison operators (all spellings of the reference, §2.4).
COMPARISONS: frozenset[str] = frozenset({"=", "<>", "><", "<", "<=", "=<", ">", ">=", "=>"})
