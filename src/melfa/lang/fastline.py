"""The commonest line shapes read by regular expressions, without tokens: a fast path of the
parser for the lines it reads most.

Lexing a line token by token and parsing it by recursive descent costs about 120,000
machine instructions a line in CPython, most of it the interpreter's work per token and per
call, not the language's (bench/bench_check.py). Most lines of real programs have one of a
few shapes: a comment, a label, ``MOV P1, -50``, ``MVS P2 * (0, 0, -50, 0, 0, 0)``,
``MVS P3, -80 WTH M_OUT(17) = 1``, ``HOPEN 1``, ``DLY 0.5``, ``GOSUB *PICK``, ``RETURN``,
``M1 = M1 + 1``, ``P1.Z = P2.Z + MALT * MI``, ``MX = SIN(RAD(30)) * MD``, ``M_OUT(17) = 1
DLY 0.5``, ``IF M_IN(8) = 1 THEN *L``, ``IF M_IN(3) = 1 THEN M_OUT(25) = 1 ELSE HLT``,
``FOR MI = 1 TO 3``, ``WHILE MC < 10``, ``NEXT MI``. `read_line` reads such a line with a
few regular-expression matches (one for the line, one for each operand and operator) and
builds its tree directly, and returns None for every other line (``^``, a string, ``DEF``,
``TYPE``, ``WTHIF``, a mistake…), which the lexer and the parser then read as before
(`melfa.lang.reparse`).

The tree is the parser's, field for field (``tests/lang/test_fastline.py`` compares the two
on every line of the golden corpus written ten ways, and on lines made to be near misses):
each pattern follows the lexer's token rules (a word, a number, a label ends where the
lexer's would; a keyword is never read as a name), operators are climbed by the parser's own
precedence table, and a line that is anything but plainly right goes to the parser, which
also says what is wrong with it. No line read here has a parse issue.
"""

from __future__ import annotations

import re
from collections.abc import Callable

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.grammar import BINARY as _BINARY
from melfa.lang.grammar import COMMANDS as _COMMANDS
from melfa.lang.model import foreign_constructs
from melfa.lang.tokens import FUNCTIONS, KEYWORDS

_new_tuple = tuple.__new__
_Span = A.Span

# A word as the lexer reads it, when it has no `#` (MELFA BASIC V's double suffix, or the
# operator `#`: the parser's) and is not the comment word REM.
_WORD = r"(?!(?i:REM)(?![A-Za-z0-9_$%!]))[A-Za-z][A-Za-z0-9_]*+[$%!]?+(?!\#)"
# Numbers the lexer reads as INTEGER or REAL, without an exponent or a `#` suffix (the
# parser's: an exponent is rare, a suffix is an issue).
_INT = r"\d++(?![.\#Ee])"
_REAL = r"(?:\d++\.\d*+|\.\d++)(?![\#Ee])"

# The line: step number, label, the first word, the rest up to the comment, the line end.
_LINE = re.compile(
    rf"""
    [ \t]*+
    (?:(?P<num>\d++)(?![.\#A-Za-z_$%!])[ \t]*+)?
    (?:\*(?P<label>[A-Za-z][A-Za-z0-9_]*+[$%!]?+)(?![\#.])[ \t]*+)?
    (?P<word>{_WORD})?
    (?P<rest>[^'"\r\n]*+)
    (?:'(?P<comment>[^\r\n]*+))?
    (?:\r\n|\r|\n)?+\Z
    """,
    re.VERBOSE | re.ASCII,
)
# One value of an argument list: a signed name or number, then a comma or the end.
_ARG = re.compile(
    rf"""
    [ \t]*+
    (?:(?P<sign>[-+])[ \t]*+)?
    (?:(?P<name>{_WORD})|(?P<real>{_REAL})|(?P<int>{_INT}))
    [ \t]*+(?P<comma>,)?
    """,
    re.VERBOSE | re.ASCII,
)
# A value in parentheses (an index, a constant's element): a signed name or number, then a
# comma or the closing parenthesis.
_ITEM = re.compile(
    rf"[ \t]*+(?:(?P<sign>[-+])[ \t]*+)?(?:(?P<name>{_WORD})|(?P<real>{_REAL})|(?P<int>{_INT}))"
    r"[ \t]*+(?P<sep>[,)])",
    re.ASCII,
)
# An operand: a signed name, number or constant, then the parenthesis of a name's index,
# or a name's element.
_TERM = re.compile(
    rf"[ \t]*+(?:(?P<sign>[-+])[ \t]*+)?"
    rf"(?:(?P<name>{_WORD})|(?P<real>{_REAL})|(?P<int>{_INT})|(?P<paren>\())"
    r"(?P<index>[ \t]*+\()?(?:[ \t]*+\.(?P<element>[A-Za-z][A-Za-z0-9_]*+))?",
    re.ASCII,
)
# The operators read here, as the lexer splits them (not ^, << or >>: the parser's).
_OPERATOR = re.compile(
    r"[ \t]*+(<>|><|<=|=<|>=|=>|[-+*/\\]|[=<>](?![<>=])|(?i:AND|OR|XOR|MOD)(?![A-Za-z0-9_$%!\#]))",
    re.ASCII,
)
_TARGET = re.compile(
    r"[ \t]*+(?:\*(?P<label>[A-Za-z][A-Za-z0-9_]*+[$%!]?+)|(?P<int>\d++))", re.ASCII
)
_NAME = re.compile(rf"[ \t]*+(?P<name>{_WORD})", re.ASCII)
_COMMA = re.compile(r"[ \t]*+,", re.ASCII)
# ELSE as the lexer reads the word (not inside another word, not a label or an element).
_ELSE = re.compile(r"(?<![A-Za-z0-9_$%!.#*])(?i:ELSE)(?![A-Za-z0-9_$%!#])", re.ASCII)
_SEPARATOR = re.compile(r"[ \t]*+([,)])", re.ASCII)
_OPEN = re.compile(r"[ \t]*+\(", re.ASCII)
_MAX_NESTING = 16  # parentheses in one line read by `_values` (the parser allows 64 levels)
_ASSIGN = re.compile(r"[ \t]*+(?:(?P<element>\.[A-Za-z][A-Za-z0-9_]*+)[ \t]*+)?=", re.ASCII)

_ELEMENTS = {k.value: k for k in A.ElementKind}
_FOREIGN = foreign_constructs()
_INTEGER, _REAL_KIND = A.NumberKind.INTEGER, A.NumberKind.REAL
_MINUS, _PLUS = A.UnaryOp.MINUS, A.UnaryOp.PLUS


def _to_int(text: str) -> int:
    return int(text) if len(text) <= 40 else 10**40  # as the parser reads it


def _args(piece: str, pos: int, end: int, line: int) -> list[A.Expr] | None:
    """The values of ``a, -b, 0.5`` in ``piece[pos:end]``, or None (not that shape)."""
    items: list[A.Expr] = []
    match = _ARG.match
    while True:
        m = match(piece, pos, end)
        if m is None:
            return None
        node = _atom(m, line)
        if node is None:
            return None
        items.append(node)
        pos = m.end()
        if m["comma"] is None:
            return items if pos == end else None


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
        node = A.Number(value, _INTEGER, integer, span)
    else:
        at, after = m.span(3)
        span = _new_tuple(_Span, (line, at + 1, line, after + 1))
        node = A.Number(float(real), _REAL_KIND, real, span)
    if sign is not None:
        node = A.Unary(
            _MINUS if sign == "-" else _PLUS,
            node,
            _new_tuple(_Span, (line, m.start(1) + 1, line, after + 1)),
        )
    return node


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
        node: A.Expr = A.Number(int(text), _INTEGER, text, span)
        if signed:
            span = _new_tuple(_Span, (line, first + 1, line, at + 1 + len(text)))
            node = A.Unary(_MINUS if sign == "-" else _PLUS, node, span)
        items.append(node)
    return items


def _items(piece: str, pos: int, end: int, line: int) -> tuple[list[A.Expr], int] | None:
    """After a `(`: the values up to the `)`, and the offset after it; or None."""
    close = piece.find(")", pos, end)
    if close > pos:
        numbers = _whole_numbers(piece, pos, close, line)
        if numbers is not None:
            return numbers, close + 1
    items: list[A.Expr] = []
    match = _ITEM.match
    while True:
        m = match(piece, pos, end)
        if m is None:
            return None
        node = _atom(m, line)
        if node is None:
            return None
        items.append(node)
        pos = m.end()
        if m["sep"] == ")":
            return items, pos


def _values(piece: str, pos: int, end: int, line: int) -> tuple[list[A.Expr], int] | None:
    """After a `(`: expressions up to the `)` (``SIN(RAD(30))``, ``M_IN(MI + 1)``), and the
    offset after it; or None. Nested at most `_MAX_NESTING` deep, far within the parser's
    limit (it reports a deeper nesting)."""
    if piece.count("(", pos, end) > _MAX_NESTING:
        return None
    items: list[A.Expr] = []
    while True:
        read = _expr(piece, pos, end, line)
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
    read = _items(piece, m.end(), end, line) or _values(piece, m.end(), end, line)
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
        at = m.start(1)
        span = _new_tuple(_Span, (line, at + 1, line, after + 1))
        node = A.Unary(_MINUS if sign == "-" else _PLUS, node, span)
    return node, after


def _element(
    m: re.Match[str], name: str | None, index: str | None, element: str, line: int
) -> tuple[A.Expr, int] | None:
    """``P1.X`` (signed or not) read by `_term`, or None."""
    kind = _ELEMENTS.get(element.upper())
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
        at = m.start(1)
        span = _new_tuple(_Span, (line, at + 1, line, after + 1))
        node = A.Unary(_MINUS if sign == "-" else _PLUS, node, span)
    return node, after


def _expr(piece: str, pos: int, end: int, line: int, least: int = 0) -> tuple[A.Expr, int] | None:
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
        read = _expr(piece, m.end(), end, line, prec + 1)
        if read is None:
            return None
        right, pos = read
        span = _new_tuple(_Span, (line, left.span[1], line, right.span[3]))
        left = A.Binary(kind, left, right, span, op)
    return left, pos


# A statement reader: (piece, word's offset, word upper-cased, rest's start, rest's end,
# line number) -> the statement, or None.
_Reader = Callable[[str, int, str, int, int, int], A.Statement | None]


def _move(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    """``MOV target[, close] [WTH action]`` (``MVS`` alike)."""
    read = _expr(piece, pos, end, line)
    if read is None:
        return None
    target, after = read
    close = appended = None
    if after != end:
        m = None if piece[after] == "," else _COMMA.match(piece, after, end)
        if m is not None or piece[after] == ",":
            read = _expr(piece, after + 1 if m is None else m.end(), end, line)
            if read is None:
                return None
            close, after = read
        if after != end:
            appended = _with(piece, after, end, line)
            if appended is None:
                return None
    kind = A.MoveKind.MOV if word == "MOV" else A.MoveKind.MVS
    span = _new_tuple(_Span, (line, at + 1, line, end + 1))
    return A.Move(kind, target, close, None, appended, span)


def _with(piece: str, pos: int, end: int, line: int) -> A.Appended | None:
    """``WTH M_OUT(17) = 1`` (with or without a DLY pulse), ``WTH HLT``, ``WTH SKIP`` from
    `pos` to `end`; or None."""
    word, after = _word(piece, pos, end)
    if word != "WTH":
        return None
    span = _new_tuple(_Span, (line, after - 2, line, end + 1))  # from WTH to the end
    action, start = _word(piece, after, end)
    if action in ("HLT", "SKIP"):
        if start != end:
            return None
        kind = A.CommandKind.HLT if action == "HLT" else A.CommandKind.SKIP
        where = _new_tuple(_Span, (line, end + 1 - len(action), line, end + 1))
        command = A.Command(kind, (), where)
        return A.Appended(None, command, span)
    if not action or action in KEYWORDS:
        return None
    at = start - len(action)
    assign = _assign(piece, at, piece[at:start], start, end, line)
    return None if assign is None else A.Appended(None, assign, span)


def _command(kind: A.CommandKind, lo: int, hi: int) -> _Reader:
    def read(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
        whole = _new_tuple(_Span, (line, at + 1, line, end + 1))
        digits = piece[pos:end].lstrip(" \t")
        if digits.isdigit() and digits.isascii() and lo <= 1 <= hi and len(digits) <= 40:
            # One whole number (``HOPEN 1``, ``OVRD 30``), the commonest argument: `_args`'
            # node, without a pattern.
            span = _new_tuple(_Span, (line, end + 1 - len(digits), line, end + 1))
            return A.Command(kind, (A.Number(int(digits), _INTEGER, digits, span),), whole)
        args = _args(piece, pos, end, line) if pos < end else []
        if args is None or not lo <= len(args) <= hi:
            return None
        # The last value ends the line's statement (at `end`), as the word does without one.
        return A.Command(kind, tuple(args), whole)

    return read


def _target(piece: str, pos: int, end: int, line: int) -> A.JumpTarget | None:
    """``*LABEL`` or a step number from `pos` to `end`, or None."""
    m = _TARGET.fullmatch(piece, pos, end)
    if m is None:
        return None
    label = m["label"]
    if label is not None:
        s = m.start("label")  # after the `*`
        return A.LabelRef(label.upper(), _new_tuple(_Span, (line, s, line, end + 1)), label)
    s = m.start("int")
    return A.LineRef(_to_int(m["int"]), _new_tuple(_Span, (line, s + 1, line, end + 1)))


def _jump(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    target = _target(piece, pos, end, line)
    if target is None:
        return None
    whole = _new_tuple(_Span, (line, at + 1, line, end + 1))
    return A.Goto(target, whole) if word == "GOTO" else A.Gosub(target, whole)


def _return(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    if pos == end:
        return A.Return(None, _new_tuple(_Span, (line, at + 1, line, at + 7)))
    args = _args(piece, pos, end, line)
    if args is None or len(args) != 1:
        return None
    return A.Return(args[0], _new_tuple(_Span, (line, at + 1, line, end + 1)))


def _bare(make: Callable[[A.Span], A.Statement]) -> _Reader:
    def read(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
        if pos != end:
            return None
        return make(_new_tuple(_Span, (line, at + 1, line, at + 1 + len(word))))

    return read


def _next(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    if pos == end:
        return A.Next((), _new_tuple(_Span, (line, at + 1, line, at + 5)))
    m = _NAME.fullmatch(piece, pos, end)
    if m is None:
        return None
    name = m["name"]
    upper = name.upper()
    if upper in KEYWORDS:
        return None
    s = m.start("name")
    counter = A.Name(upper, _new_tuple(_Span, (line, s + 1, line, end + 1)), name)
    return A.Next((counter,), _new_tuple(_Span, (line, at + 1, line, end + 1)))


def _assign(piece: str, at: int, name: str, pos: int, end: int, line: int) -> A.Statement | None:
    """``NAME = value``, ``NAME.X = value``, ``M_OUT(17) = 1`` or ``M_OUT(17) = 1 DLY 0.5``
    (`name` as written)."""
    base = A.Name(name.upper(), _new_tuple(_Span, (line, at + 1, line, at + 1 + len(name))), name)
    target: A.AssignTarget = base
    m = _ASSIGN.match(piece, pos, end)
    if m is None:
        m = _OPEN.match(piece, pos, end)
        if m is None:
            return None
        listed = _items(piece, m.end(), end, line) or _values(piece, m.end(), end, line)
        if listed is None:
            return None
        items, pos = listed
        target = A.Index(base, tuple(items), _new_tuple(_Span, (line, at + 1, line, pos + 1)))
        m = _ASSIGN.match(piece, pos, end)
        if m is None:
            return None
    element = m["element"]
    if element is not None:
        kind = _ELEMENTS.get(element[1:].upper())
        if kind is None:
            return None
        stop = m.end("element") + 1
        target = A.Element(target, kind, _new_tuple(_Span, (line, at + 1, line, stop)))
    if (element is not None or type(target) is A.Index) and name.upper() in _FOREIGN:
        return None  # a MELFA BASIC V statement (``Print(1) = …``): the parser says so
    read = _expr(piece, m.end(), end, line)
    if read is None:
        return None
    value, after = read
    pulse = None
    if after != end:
        word, after = _word(piece, after, end)
        if word != "DLY":
            return None
        read = _expr(piece, after, end, line)
        if read is None or read[1] != end:
            return None
        pulse = read[0]
    return A.Assign(target, value, pulse, _new_tuple(_Span, (line, at + 1, line, end + 1)))


def _word(piece: str, pos: int, end: int) -> tuple[str, int]:
    """The word at `pos` upper-cased and the offset after it, or ("", pos)."""
    m = _NAME.match(piece, pos, end)
    return ("", pos) if m is None else (m[1].upper(), m.end())


def _if(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    """``IF condition THEN branch [ELSE branch]``, a branch a jump target (``*L``, ``100``)
    or a statement (``GOSUB *L``, ``M_OUT(25) = 1``, ``HLT``); or a block IF's first line."""
    read = _expr(piece, pos, end, line)
    if read is None:
        return None
    condition, after = read
    then, after = _word(piece, after, end)
    if then != "THEN":
        return None
    whole = _new_tuple(_Span, (line, at + 1, line, end + 1))
    if after == end:
        return A.If(condition, None, None, whole)
    m = _ELSE.search(piece, after, end)
    stop = end if m is None else len(piece[: m.start()].rstrip(" \t"))
    branch = _branch(piece, after, stop, line) if stop > after else None
    if branch is None:
        return None
    if m is None:
        return A.If(condition, branch, None, whole)
    other = _branch(piece, m.end(), end, line) if m.end() != end else None
    return None if other is None else A.If(condition, branch, other, whole)


def _branch(piece: str, pos: int, end: int, line: int) -> A.JumpTarget | A.Statement | None:
    """What THEN or ELSE does, from `pos` to `end`: a jump target or a statement; or None."""
    word, start = _word(piece, pos, end)
    if not word:
        return _target(piece, pos, end, line)
    at = start - len(word)
    if word in KEYWORDS:
        reader = _BRANCH_READERS.get(word)
        return None if reader is None else reader(piece, at, word, start, end, line)
    return _assign(piece, at, piece[at:start], start, end, line)


def _for(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    """``FOR M = start TO end [STEP step]``."""
    m = _NAME.match(piece, pos, end)
    if m is None or m[1].upper() in KEYWORDS:
        return None
    s = m.start(1)
    counter = A.Name(m[1].upper(), _new_tuple(_Span, (line, s + 1, line, m.end() + 1)), m[1])
    m = _ASSIGN.match(piece, m.end(), end)
    if m is None or m["element"] is not None:
        return None
    values: list[A.Expr] = []
    after = m.end()
    for expected in ("TO", "STEP", None):
        read = _expr(piece, after, end, line)
        if read is None:
            return None
        values.append(read[0])
        after = read[1]
        if after == end:
            break
        word, after = _word(piece, after, end)
        if word != expected:
            return None  # also anything after the step
    if len(values) < 2:
        return None
    step = values[2] if len(values) == 3 else None
    whole = _new_tuple(_Span, (line, at + 1, line, end + 1))
    return A.For(counter, values[0], values[1], step, whole)


def _while(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    read = _expr(piece, pos, end, line)
    if read is None or read[1] != end:
        return None
    return A.While(read[0], _new_tuple(_Span, (line, at + 1, line, end + 1)))


def _readers() -> dict[str, _Reader]:
    """Statement word -> its reader; plain commands from the parser's own table."""
    readers: dict[str, _Reader] = {
        word: _command(kind, lo, hi) for word, (kind, lo, hi, _) in _COMMANDS.items()
    }
    readers.update(
        MOV=_move,
        MVS=_move,
        GOTO=_jump,
        GOSUB=_jump,
        RETURN=_return,
        NEXT=_next,
        IF=_if,
        FOR=_for,
        WHILE=_while,
        END=_bare(lambda span: A.Command(A.CommandKind.END, (), span)),
        WEND=_bare(A.Wend),
        ELSE=_bare(A.Else),
        ENDIF=_bare(A.EndIf),
        BREAK=_bare(A.Break),
        DEFAULT=_bare(A.Default),
    )
    return readers


_READERS = _readers()
# What a THEN or ELSE branch may do here: the statements whose parser stops at ELSE (not a
# nested IF, which would take the ELSE, nor NEXT, FOR or the block words: the parser's).
_BRANCH_READERS = {
    word: _READERS[word]
    for word in (*_COMMANDS, "MOV", "MVS", "GOTO", "GOSUB", "RETURN", "END")
    if word in _READERS
}


def read_line(piece: str, line: int) -> A.Line | None:
    """The tree of text line number `line`, `piece` (with its line end, if any), when it has
    one of the shapes read here; otherwise None (the parser reads it)."""
    m = _LINE.match(piece)
    if m is None:
        return None
    digits, label_text, word, rest, comment = m.groups()
    pos = m.start(4)
    end = pos + len(rest.rstrip(" \t"))
    statement: A.Statement | None = None
    if word is not None:
        at = m.start(3)
        upper = word.upper()
        reader = _READERS.get(upper)
        if reader is not None:
            statement = reader(piece, at, upper, pos, end, line)
        elif upper in KEYWORDS:
            return None
        else:
            statement = _assign(piece, at, word, pos, end, line)
        if statement is None:
            return None
    elif pos != end:
        return None
    number = label = number_span = label_span = None
    if digits is not None:
        s = m.start(1)
        number = _to_int(digits)
        number_span = _new_tuple(_Span, (line, s + 1, line, s + 1 + len(digits)))
    if label_text is not None:
        s = m.start(2)  # after the `*`
        label = label_text.upper()
        label_span = _new_tuple(_Span, (line, s, line, s + 1 + len(label_text)))
    stop = len(piece.rstrip("\r\n"))
    return A.Line(
        number,
        label,
        statement,
        _new_tuple(_Span, (line, 1, line, stop + 1)),
        comment,
        (),
        number_span,
        label_span,
        label_text,
    )


__all__ = ["read_line"]
