"""The values of a line read by regular expressions, without tokens: operands, argument
lists and expressions, for `melfa.lang.fastline` (which reads the line and its statement).

Each pattern follows the lexer's token rules (a word, a number ends where the lexer's would;
a keyword is never read as a name), operators are climbed by the parser's own precedence
table (`melfa.lang.grammar.BINARY`), and a value that is anything but plainly right gives
None, so that the lexer and the parser read the line (and say what is wrong with it). The
commonest values (a whole number, a list of them) are read by str methods: each pattern
match costs a few thousand machine instructions, most of them the call's, not the text's.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.grammar import BINARY as _BINARY
from melfa.lang.tokens import FUNCTIONS, KEYWORDS

_new_tuple = tuple.__new__
_Span = A.Span

# A word as the lexer reads it, when it has no `#` (MELFA BASIC V's double suffix, or the
# operator `#`: the parser's) and is not the comment word REM.
WORD = r"(?!(?i:REM)(?![A-Za-z0-9_$%!]))[A-Za-z][A-Za-z0-9_]*+[$%!]?+(?!\#)"
# Numbers the lexer reads as INTEGER or REAL, without an exponent or a `#` suffix (the
# parser's: an exponent is rare, a suffix is an issue).
_INT = r"\d++(?![.\#Ee])"
_REAL = r"(?:\d++\.\d*+|\.\d++)(?![\#Ee])"

# One value of an argument list: a signed name or number, then a comma or the end.
_ARG = re.compile(
    rf"""
    [ \t]*+
    (?:(?P<sign>[-+])[ \t]*+)?
    (?:(?P<name>{WORD})|(?P<real>{_REAL})|(?P<int>{_INT}))
    [ \t]*+(?P<comma>,)?
    """,
    re.VERBOSE | re.ASCII,
)
# A value in parentheses (an index, a constant's element): a signed name or number, then a
# comma or the closing parenthesis.
_ITEM = re.compile(
    rf"[ \t]*+(?:(?P<sign>[-+])[ \t]*+)?(?:(?P<name>{WORD})|(?P<real>{_REAL})|(?P<int>{_INT}))"
    r"[ \t]*+(?P<sep>[,)])",
    re.ASCII,
)
# An operand: a signed name, number or constant, then the parenthesis of a name's index,
# or a name's element.
_TERM = re.compile(
    rf"[ \t]*+(?:(?P<sign>[-+])[ \t]*+)?"
    rf"(?:(?P<name>{WORD})|(?P<real>{_REAL})|(?P<int>{_INT})|(?P<paren>\())"
    r"(?P<index>[ \t]*+\()?(?:[ \t]*+\.(?P<element>[A-Za-z][A-Za-z0-9_]*+))?",
    re.ASCII,
)
# The operators read here, as the lexer splits them (not ^, << or >>: the parser's).
_OPERATOR = re.compile(
    r"[ \t]*+(<>|><|<=|=<|>=|=>|[-+*/\\]|[=<>](?![<>=])|(?i:AND|OR|XOR|MOD)(?![A-Za-z0-9_$%!\#]))",
    re.ASCII,
)

_SEPARATOR = re.compile(r"[ \t]*+([,)])", re.ASCII)
_MAX_NESTING = 16  # parentheses in one line read by `values` (the parser allows 64 levels)

ELEMENTS = {k.value: k for k in A.ElementKind}
INTEGER, _REAL_KIND = A.NumberKind.INTEGER, A.NumberKind.REAL
_MINUS, _PLUS = A.UnaryOp.MINUS, A.UnaryOp.PLUS


def to_int(text: str) -> int:
    return int(text) if len(text) <= 40 else 10**40  # as the parser reads it


def read_args(piece: str, pos: int, end: int, line: int) -> list[A.Expr] | None:
    """The values of ``a, -b, 0.5`` in ``piece[pos:end]``, or None (not that shape)."""
    found = _atoms(_ARG.match, piece, pos, end, line)
    if found is None:
        return None
    items, last = found
    return items if last.end() == end else None


def _atoms(
    match: Callable[[str, int, int], re.Match[str] | None],
    piece: str,
    pos: int,
    end: int,
    line: int,
) -> tuple[list[A.Expr], re.Match[str]] | None:
    """Values read one after another by `match` (`_ARG`'s or `_ITEM`'s, whose fifth group is
    what follows a value) while a comma follows: the values and the last match; or None."""
    items: list[A.Expr] = []
    while True:
        m = match(piece, pos, end)
        if m is None:
            return None
        node = _atom(m, line)
        if node is None:
            return None
        items.append(node)
        if m[5] != ",":
            return items, m
        pos = m.end()


def _atom(m: re.Match[str], line: int) -> A.Expr | None:
    """The node of groups 1-4 of `m` (sign, name, real, integer), or None (a keyword)."""
    sign, name, real, integer = m.group(1, 2, 3, 4)
    if name is not None:
        upper = name.upper()
        if upper in KEYWORDS:
            return None
        at, after = m.span(2)
        node: A.Expr = A.Name(upper, _new_tuple(_Span, (line, at + 1, line, after + 1)), name)
    elif integer is not None:
        at, after = m.span(4)
        value = int(integer) if after - at <= 40 else 10**40  # as the parser reads it
        span = _new_tuple(_Span, (line, at + 1, line, after + 1))
        node = A.Number(value, INTEGER, integer, span)
    else:
        at, after = m.span(3)
        span = _new_tuple(_Span, (line, at + 1, line, after + 1))
        node = A.Number(float(real), _REAL_KIND, real, span)
    return node if sign is None else _signed(node, sign, m.start(1), after, line)


def _signed(node: A.Expr, sign: str, at: int, after: int, line: int) -> A.Expr:
    """`node` after its sign `sign` (at offset `at`; `node` ends at offset `after`)."""
    span = _new_tuple(_Span, (line, at + 1, line, after + 1))
    return A.Unary(_MINUS if sign == "-" else _PLUS, node, span)


def _whole_numbers(piece: str, pos: int, end: int, line: int) -> list[A.Expr] | None:
    """``0, 0, -50, 0, 0, 0`` or ``8`` in ``piece[pos:end]``: whole numbers, each signed or
    not, split by commas; or None. A position constant's elements and an input's number are
    mostly these: read with str methods, several times cheaper than `_ITEM` per value."""
    items: list[A.Expr] = []
    for part in piece[pos:end].split(","):
        start = pos  # the part's offset
        pos += len(part) + 1
        text = part.lstrip(" \t")
        at = start + len(part) - len(text)  # its sign's or its digits'
        sign = text[:1]
        signed = sign == "-" or sign == "+"
        if signed:
            first = at
            after_sign = text[1:]
            text = after_sign.lstrip(" \t")
            at += 1 + len(after_sign) - len(text)
        text = text.rstrip(" \t")
        if not (text.isdigit() and text.isascii()) or len(text) > 40:
            return None
        span = _new_tuple(_Span, (line, at + 1, line, at + 1 + len(text)))
        node: A.Expr = A.Number(int(text), INTEGER, text, span)
        if signed:
            node = _signed(node, sign, first, at + len(text), line)
        items.append(node)
    return items


def read_items(piece: str, pos: int, end: int, line: int) -> tuple[list[A.Expr], int] | None:
    """After a `(`: the values up to the `)`, and the offset after it; or None."""
    close = piece.find(")", pos, end)
    if close > pos:
        numbers = _whole_numbers(piece, pos, close, line)
        if numbers is not None:
            return numbers, close + 1
    found = _atoms(_ITEM.match, piece, pos, end, line)
    if found is None:
        return None
    items, last = found  # followed by `)`, the only other separator `_ITEM` reads
    return items, last.end()


def read_values(piece: str, pos: int, end: int, line: int) -> tuple[list[A.Expr], int] | None:
    """After a `(`: expressions up to the `)` (``SIN(RAD(30))``, ``M_IN(MI + 1)``), and the
    offset after it; or None. Nested at most `_MAX_NESTING` deep, far within the parser's
    limit (it reports a deeper nesting)."""
    if piece.count("(", pos, end) > _MAX_NESTING:
        return None
    items: list[A.Expr] = []
    while True:
        read = read_expr(piece, pos, end, line)
        if read is None:
            return None
        node, pos = read
        m = _SEPARATOR.match(piece, pos, end)
        if m is None:
            return None
        items.append(node)
        pos = m.end()
        if m[1] == ")":
            return items, pos


def _term(piece: str, pos: int, end: int, line: int) -> tuple[A.Expr, int] | None:
    """An operand at `pos`: a signed name, number, ``M_IN(8)`` or ``(0, 0, -50, 0, 0, 0)``,
    and the offset after it; or None."""
    m = _TERM.match(piece, pos, end)
    if m is None:
        return None
    sign, name, _, _, paren, index, element = m.groups()
    if element is not None:
        return _element(m, name, index, element, line)
    if paren is None and index is None:
        if sign is not None or name is None:
            node = _atom(m, line)
            return None if node is None else (node, m.end())
        upper = name.upper()  # an unsigned name, the commonest operand: `_atom`'s, inline
        if upper in KEYWORDS:
            return None
        at, after = m.span(2)
        return A.Name(upper, _new_tuple(_Span, (line, at + 1, line, after + 1)), name), m.end()
    if (name is None and paren is None) or (paren is not None and index is not None):
        return None  # `5 (`, `((`
    read = read_items(piece, m.end(), end, line) or read_values(piece, m.end(), end, line)
    if read is None:
        return None
    items, after = read
    if paren is not None:
        if piece[after:end].lstrip(" \t")[:1] == "(":
            return None  # a constant with flags: the parser's
        if len(items) == 1:
            node = items[0]  # a value in parentheses is the value (its span without them)
        else:
            at = m.start(5)
            span = _new_tuple(_Span, (line, at + 1, line, after + 1))
            node = A.PositionLiteral(tuple(items), None, span)
    else:
        upper = name.upper()
        at = m.start(2)
        whole = _new_tuple(_Span, (line, at + 1, line, after + 1))
        if upper in KEYWORDS:
            if upper not in FUNCTIONS:
                return None
            node = A.Call(upper, tuple(items), False, whole)
        elif upper.startswith("FN"):
            node = A.Call(upper, tuple(items), True, whole)
        else:
            span = _new_tuple(_Span, (line, at + 1, line, at + 1 + len(name)))
            node = A.Index(A.Name(upper, span, name), tuple(items), whole)
    if sign is not None:
        node = _signed(node, sign, m.start(1), after, line)
    return node, after


def _element(
    m: re.Match[str], name: str | None, index: str | None, element: str, line: int
) -> tuple[A.Expr, int] | None:
    """``P1.X`` (signed or not) read by `_term`, or None."""
    kind = ELEMENTS.get(element.upper())
    if name is None or index is not None or kind is None:
        return None  # `P(1).X`, `5 .X`, `P1.Q`: the parser's
    upper = name.upper()
    if upper in KEYWORDS:
        return None
    at, after = m.start(2), m.end()
    base = A.Name(upper, _new_tuple(_Span, (line, at + 1, line, at + 1 + len(name))), name)
    node: A.Expr = A.Element(base, kind, _new_tuple(_Span, (line, at + 1, line, after + 1)))
    sign = m.group(1)
    if sign is not None:
        node = _signed(node, sign, m.start(1), after, line)
    return node, after


def read_expr(
    piece: str, pos: int, end: int, line: int, least: int = 0
) -> tuple[A.Expr, int] | None:
    """Operands joined by arithmetic, comparison and logical operators, by the parser's
    precedence climbing (`least`: the lowest precedence read here), and the offset after;
    or None. What may follow is the callers' to check."""
    read = _term(piece, pos, end, line)
    if read is None:
        return None
    left, pos = read
    while pos != end and piece[pos] not in ",)":  # no operator next, without a match
        m = _OPERATOR.match(piece, pos, end)
        if m is None:
            break
        op = m.group(1).upper()
        prec, kind = _BINARY[op]
        if prec < least:
            break
        read = read_expr(piece, m.end(), end, line, prec + 1)
        if read is None:
            return None
        right, pos = read
        span = _new_tuple(_Span, (line, left.span[1], line, right.span[3]))
        left = A.Binary(kind, left, right, span, op)
    return left, pos
