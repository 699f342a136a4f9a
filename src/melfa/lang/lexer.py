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

from melfa.lang.tokens import KEYWORDS, Token, TokenKind

# One alternative per token kind; the leading group captures the whitespace prefix.
# re.ASCII keeps `[A-Z]` from matching look-alike Unicode letters under IGNORECASE.
_MASTER = re.compile(
    r"""
    (?P<ws>[ \t]*)
    (?:
      (?P<NEWLINE>\r\n|\r|\n)
    | (?P<COMMENT>'[^\r\n]*|REM(?![A-Z0-9_$%!])[^\r\n]*)
    | (?P<STRING>"[^"\r\n]*")
    | (?P<USTRING>"[^"\r\n]*)
    | (?P<HEX>&H[0-9A-F]+)
    | (?P<BIN>&B[01]+)
    | (?P<REAL>(?:\d+\.\d*|\.\d+)(?:E[+-]?\d+)?|\d+E[+-]?\d+)
    | (?P<INTEGER>\d+)
    | (?P<DOT>\.[A-Z][A-Z0-9_]*)
    | (?P<LABEL>\*[A-Z][A-Z0-9_]*[$%!]?)
    | (?P<WORD>[A-Z][A-Z0-9_]*[$%!]?)
    | (?P<OP><>|><|<=|=<|>=|=>|<<|>>|[-+*/\\^=<>\#;])
    | (?P<COMMA>,)
    | (?P<LPAREN>\()
    | (?P<RPAREN>\))
    | (?P<EOF>\Z)
    | (?P<ERROR>[\s\S])
    )
    """,
    re.IGNORECASE | re.ASCII | re.VERBOSE,
)

_SIMPLE_KINDS: dict[str, TokenKind] = {
    "NEWLINE": TokenKind.NEWLINE,
    "COMMENT": TokenKind.COMMENT,
    "STRING": TokenKind.STRING,
    "USTRING": TokenKind.ERROR,
    "HEX": TokenKind.HEX,
    "BIN": TokenKind.BIN,
    "REAL": TokenKind.REAL,
    "INTEGER": TokenKind.INTEGER,
    "DOT": TokenKind.DOT_ELEMENT,
    "LABEL": TokenKind.LABEL,
    "OP": TokenKind.OP,
    "COMMA": TokenKind.COMMA,
    "LPAREN": TokenKind.LPAREN,
    "RPAREN": TokenKind.RPAREN,
    "EOF": TokenKind.EOF,
    "ERROR": TokenKind.ERROR,
}

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


def _word_kind(word: str) -> TokenKind:
    return TokenKind.KEYWORD if word.upper() in KEYWORDS else TokenKind.IDENT


def tokenize(text: str) -> list[Token]:
    """Split `text` into tokens; the last one is EOF. Never raises.

    >>> [(t.kind.name, t.text) for t in tokenize("10 MOV P1*P2\\n")][:5]
    [('LINE_NUMBER', '10'), ('KEYWORD', 'MOV'), ('IDENT', 'P1'), ('OP', '*'), ('IDENT', 'P2')]
    >>> t = tokenize("GOTO *LOOP")[1]
    >>> (t.kind.name, t.line, t.column, t.end_column)
    ('LABEL', 1, 6, 11)
    """
    tokens: list[Token] = []
    append = tokens.append
    new = tuple.__new__  # Token(...) without the Python-level __new__: this loop is hot
    line = 1
    line_start = 0
    prev = TokenKind.NEWLINE  # the kind of the previous token; start of text = new line
    kind_of = _SIMPLE_KINDS
    keywords = KEYWORDS
    t_newline = TokenKind.NEWLINE
    t_keyword = TokenKind.KEYWORD
    t_ident = TokenKind.IDENT
    t_integer = TokenKind.INTEGER
    for m in _MASTER.finditer(text):
        group = m.lastgroup
        ws_start, start = m.span(1)
        end = m.end()
        tok = text[start:end]
        col = start - line_start + 1
        if group == "WORD":
            kind = t_keyword if tok.upper() in keywords else t_ident
        elif group == "INTEGER":
            kind = TokenKind.LINE_NUMBER if prev is t_newline else t_integer
        elif group == "LABEL" and prev in _OPERAND_END:
            prefix = text[ws_start:start]
            append(new(Token, (TokenKind.OP, "*", line, col, line, col + 1, prefix)))
            word = tok[1:]
            kind = _word_kind(word)
            append(new(Token, (kind, word, line, col + 1, line, col + len(tok), "")))
            prev = kind
            continue
        else:
            kind = kind_of[group]  # type: ignore[index]
            if kind is t_newline:
                prefix = text[ws_start:start]
                append(new(Token, (kind, tok, line, col, line + 1, 1, prefix)))
                line += 1
                line_start = end
                prev = kind
                continue
        append(new(Token, (kind, tok, line, col, line, col + len(tok), text[ws_start:start])))
        prev = kind
    return tokens


def untokenize(tokens: list[Token]) -> str:
    """The exact text the tokens came from.

    >>> untokenize(tokenize("10 mov  p1 ' go\\r\\n"))
    "10 mov  p1 ' go\\r\\n"
    """
    return "".join(t.prefix + t.text for t in tokens)
