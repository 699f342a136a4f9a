"""The lexer: text to tokens, losslessly, in one compiled regular expression.

`tokenize` never fails: a character the language does not have becomes an ERROR token and
the rest of the text is still tokenized. Two decisions need one token of context and are
taken while the matches stream past:

* an integer is a LINE_NUMBER when it is the first token of a line;
* ``*NAME`` is a LABEL unless it follows an operand (``P1*P2`` is a product), in which case
  it is split into the operator ``*`` and a word.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from itertools import count

from melfa.lang.tokens import KEYWORDS, Token, TokenKind

# The whitespace before a token, then the token: one alternative per token kind, in this
# order (the first that matches wins). `findall` returns (whitespace, token) pairs without a
# match object per token, and the token's first character then tells its kind (see
# `_FIRST`): this loop runs on every keystroke, over every token of the program.
# re.ASCII keeps `[A-Z]` from matching look-alike Unicode letters under IGNORECASE.
_MASTER = re.compile(
    r"""
    ([ \t]*)
    (
      \r\n|\r|\n                                  # NEWLINE
    | '[^\r\n]*|REM(?![A-Z0-9_$%!])[^\r\n]*       # COMMENT
    | "[^"\r\n]*"?                                # STRING, or ERROR when not closed
    | &H[0-9A-F]+ | &B[01]+                       # HEX, BIN
    | (?:\d+\.\d*|\.\d+)(?:E[+-]?\d+)?\#?|\d+E[+-]?\d+\#?|\d+\#(?![0-9])  # REAL (V: 1.0#)
    | \d+                                         # INTEGER (or LINE_NUMBER)
    | \.[A-Z][A-Z0-9_]*                           # DOT_ELEMENT
    | \*[A-Z][A-Z0-9_]*[$%!]?                     # LABEL
    | [A-Z][A-Z0-9_]*(?:[$%!]|\#(?![0-9]))?       # a word: KEYWORD or IDENT (V: MX#)
    | <>|><|<=|=<|>=|=>|<<|>>|[-+*/\\^=<>\#;]     # OP
    | [,()]                                       # COMMA, LPAREN, RPAREN
    | \Z                                          # EOF (an empty token)
    | [\s\S]                                      # ERROR: one character
    )
    """,
    re.IGNORECASE | re.ASCII | re.VERBOSE,
)

# Markers in `_FIRST` for first characters whose kind needs a second look.
_WORD, _REM, _DIGIT, _QUOTE, _AMP, _DOT, _STAR = range(7)

# First character of a token -> its kind, or a marker. Anything else is an ERROR token.
_FIRST: dict[str, TokenKind | int] = {
    "": TokenKind.EOF,
    "\r": TokenKind.NEWLINE,
    "\n": TokenKind.NEWLINE,
    "'": TokenKind.COMMENT,
    ",": TokenKind.COMMA,
    "(": TokenKind.LPAREN,
    ")": TokenKind.RPAREN,
    '"': _QUOTE,
    "&": _AMP,
    ".": _DOT,
    "*": _STAR,
    **dict.fromkeys("-+/\\^=<>#;", TokenKind.OP),
    **dict.fromkeys("0123456789", _DIGIT),
    **dict.fromkeys("ABCDEFGHIJKLMNOPQSTUVWXYZabcdefghijklmnopqstuvwxyz", _WORD),
    "R": _REM,
    "r": _REM,
}
_WORD_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_$%!")

# After one of these, `*NAME` is multiplication, not a label.
_OPERAND_END = frozenset(
    {
        TokenKind.IDENT,
        TokenKind.INTEGER,
        TokenKind.REAL,
        TokenKind.HEX,
        TokenKind.BIN,
        TokenKind.STRING,
        TokenKind.RPAREN,
        TokenKind.DOT_ELEMENT,
    }
)


# Tokens whose kind their text alone gives (words, operators, punctuation) -> that kind: a
# program uses few words many times, and one look-up is the cheapest way to a token's kind.
# Not numbers (a LINE_NUMBER only first on a line), `*` words (labels or products), line ends.
_KNOWN: dict[str, TokenKind] = {
    **dict.fromkeys(("<>", "><", "<=", "=<", ">=", "=>", "<<", ">>", "*"), TokenKind.OP),
    **{
        tok: kind
        for tok, kind in _FIRST.items()
        if isinstance(kind, TokenKind) and kind is not TokenKind.NEWLINE
    },
}
_KNOWN_LIMIT = 20_000  # words kept (then the others are looked at each time)


def _word_kind(word: str) -> TokenKind:
    return TokenKind.KEYWORD if word.upper() in KEYWORDS else TokenKind.IDENT


def _second_look(marker: int, tok: str) -> TokenKind:
    """The kind of a token whose first character is not enough (not a word or a number)."""
    if marker == _QUOTE:
        return TokenKind.STRING if len(tok) > 1 and tok[-1] == '"' else TokenKind.ERROR
    if marker == _AMP:
        if len(tok) == 1:
            return TokenKind.ERROR
        return TokenKind.HEX if tok[1] in "Hh" else TokenKind.BIN
    if marker == _DOT:
        if len(tok) == 1:
            return TokenKind.ERROR
        return TokenKind.REAL if tok[1].isdigit() else TokenKind.DOT_ELEMENT
    return TokenKind.LABEL if len(tok) > 1 else TokenKind.OP  # _STAR


def tokenize(
    text: str, first_line: int = 1, line_numbers: Iterable[int] | None = None
) -> list[Token]:
    """Split `text` into tokens; the last one is EOF. Never raises. `first_line` is the
    number of the text's first line (a line lexed on its own, `melfa.lang.reparse`);
    `line_numbers`, when given, the numbers of the text's lines after the first (lines of a
    program gathered into one text, `melfa.lang.reparse`; the next number after the last).

    >>> [(t.kind.name, t.text) for t in tokenize("10 MOV P1*P2\\n")][:5]
    [('LINE_NUMBER', '10'), ('KEYWORD', 'MOV'), ('IDENT', 'P1'), ('OP', '*'), ('IDENT', 'P2')]
    >>> t = tokenize("GOTO *LOOP")[1]
    >>> (t.kind.name, t.line, t.column, t.end_column)
    ('LABEL', 1, 6, 11)
    """
    tokens: list[Token] = []
    append = tokens.append
    new = tuple.__new__  # Token(...) without the Python-level __new__: this loop is hot
    first = _FIRST
    keywords = KEYWORDS
    word_chars = _WORD_CHARS
    t_newline = TokenKind.NEWLINE
    t_keyword = TokenKind.KEYWORD
    t_ident = TokenKind.IDENT
    t_error = TokenKind.ERROR
    line = first_line
    next_line = (iter(line_numbers) if line_numbers is not None else count(first_line + 1)).__next__
    line_start = 0  # offset of the current line's first character
    pos = 0  # offset of the end of the previous token
    prev = t_newline  # the kind of the previous token; start of text = new line
    known = _KNOWN
    for ws, tok in _MASTER.findall(text):
        start = pos + len(ws)
        pos = start + len(tok)
        col = start - line_start + 1
        kind: TokenKind | None = known.get(tok)
        if kind is not None:  # a word or an operator seen before: most tokens
            append(new(Token, (kind, tok, line, col, line, col + len(tok), ws)))
            prev = kind
            continue
        found = first.get(tok[:1], t_error)
        if isinstance(found, int):
            if found == _WORD or (
                found == _REM
                and not (tok[:3].upper() == "REM" and (len(tok) == 3 or tok[3] not in word_chars))
            ):
                kind = t_keyword if tok.upper() in keywords else t_ident
                if len(known) < _KNOWN_LIMIT:
                    known[tok] = kind
            elif found == _REM:
                kind = TokenKind.COMMENT
            elif found == _DIGIT:
                if not tok.isdigit():
                    kind = TokenKind.REAL
                elif prev is t_newline:
                    kind = TokenKind.LINE_NUMBER
                else:
                    kind = TokenKind.INTEGER
            else:
                kind = _second_look(found, tok)
                if kind is TokenKind.LABEL and prev in _OPERAND_END:
                    # `P1*P2`: the operator * and a word, not the label *P2.
                    append(new(Token, (TokenKind.OP, "*", line, col, line, col + 1, ws)))
                    word = tok[1:]
                    kind = _word_kind(word)
                    append(new(Token, (kind, word, line, col + 1, line, col + len(tok), "")))
                    prev = kind
                    continue
        else:
            kind = found
            if kind is t_newline:
                append(new(Token, (kind, tok, line, col, line + 1, 1, ws)))
                line = next_line()
                line_start = pos
                prev = kind
                continue
        append(new(Token, (kind, tok, line, col, line, col + len(tok), ws)))
        prev = kind
    if len(tokens) > 1 and tokens[-2].kind is TokenKind.EOF:
        # Text ending in spaces without a line end: `findall` matches the EOF twice (after
        # the spaces, then empty); one EOF, or the last line read as a missing statement.
        del tokens[-1]
    return tokens


def untokenize(tokens: list[Token]) -> str:
    """The exact text the tokens came from.

    >>> untokenize(tokenize("10 mov  p1 ' go\\r\\n"))
    "10 mov  p1 ' go\\r\\n"
    """
    return "".join(t.prefix + t.text for t in tokens)
