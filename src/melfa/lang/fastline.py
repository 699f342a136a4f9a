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
(`melfa.lang.reparse`). The values in a statement (operands, argument lists,
expressions) are read by `melfa.lang.fastvalues`.

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
from melfa.lang.fastvalues import (
    ELEMENTS,
    INTEGER,
    WORD,
    read_args,
    read_expr,
    read_items,
    read_values,
    to_int,
)
from melfa.lang.grammar import COMMANDS as _COMMANDS
from melfa.lang.model import foreign_constructs
from melfa.lang.tokens import KEYWORDS

_new_tuple = tuple.__new__
_Span = A.Span


# The line: step number, label, the first word, the rest up to the comment, the line end.
_LINE = re.compile(
    rf"""
    [ \t]*+
    (?:(?P<num>\d++)(?![.\#A-Za-z_$%!])[ \t]*+)?
    (?:\*(?P<label>[A-Za-z][A-Za-z0-9_]*+[$%!]?+)(?![\#.])[ \t]*+)?
    (?P<word>{WORD})?
    (?P<rest>[^'"\r\n]*+)
    (?:'(?P<comment>[^\r\n]*+))?
    (?:\r\n|\r|\n)?+\Z
    """,
    re.VERBOSE | re.ASCII,
)
_TARGET = re.compile(
    r"[ \t]*+(?:\*(?P<label>[A-Za-z][A-Za-z0-9_]*+[$%!]?+)|(?P<int>\d++))", re.ASCII
)
_NAME = re.compile(rf"[ \t]*+(?P<name>{WORD})", re.ASCII)
_COMMA = re.compile(r"[ \t]*+,", re.ASCII)
# ELSE as the lexer reads the word (not inside another word, not a label or an element).
_ELSE = re.compile(r"(?<![A-Za-z0-9_$%!.#*])(?i:ELSE)(?![A-Za-z0-9_$%!#])", re.ASCII)
_OPEN = re.compile(r"[ \t]*+\(", re.ASCII)
_ASSIGN = re.compile(r"[ \t]*+(?:(?P<element>\.[A-Za-z][A-Za-z0-9_]*+)[ \t]*+)?=", re.ASCII)

_FOREIGN = foreign_constructs()


# A statement reader: (piece, word's offset, word upper-cased, rest's start, rest's end,
# line number) -> the statement, or None.
_Reader = Callable[[str, int, str, int, int, int], A.Statement | None]


def _move(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    """``MOV target[, close] [WTH action]`` (``MVS`` alike)."""
    read = read_expr(piece, pos, end, line)
    if read is None:
        return None
    target, after = read
    close = appended = None
    if after != end:
        m = None if piece[after] == "," else _COMMA.match(piece, after, end)
        if m is not None or piece[after] == ",":
            read = read_expr(piece, after + 1 if m is None else m.end(), end, line)
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
            # One whole number (``HOPEN 1``, ``OVRD 30``), the commonest argument: `args`'
            # node, without a pattern.
            span = _new_tuple(_Span, (line, end + 1 - len(digits), line, end + 1))
            return A.Command(kind, (A.Number(int(digits), INTEGER, digits, span),), whole)
        args = read_args(piece, pos, end, line) if pos < end else []
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
    return A.LineRef(to_int(m["int"]), _new_tuple(_Span, (line, s + 1, line, end + 1)))


def _jump(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    target = _target(piece, pos, end, line)
    if target is None:
        return None
    whole = _new_tuple(_Span, (line, at + 1, line, end + 1))
    return A.Goto(target, whole) if word == "GOTO" else A.Gosub(target, whole)


def _return(piece: str, at: int, word: str, pos: int, end: int, line: int) -> A.Statement | None:
    if pos == end:
        return A.Return(None, _new_tuple(_Span, (line, at + 1, line, at + 7)))
    args = read_args(piece, pos, end, line)
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
        listed = read_items(piece, m.end(), end, line) or read_values(piece, m.end(), end, line)
        if listed is None:
            return None
        items, pos = listed
        target = A.Index(base, tuple(items), _new_tuple(_Span, (line, at + 1, line, pos + 1)))
        m = _ASSIGN.match(piece, pos, end)
        if m is None:
            return None
    element = m["element"]
    if element is not None:
        kind = ELEMENTS.get(element[1:].upper())
        if kind is None:
            return None
        stop = m.end("element") + 1
        target = A.Element(target, kind, _new_tuple(_Span, (line, at + 1, line, stop)))
    if (element is not None or type(target) is A.Index) and name.upper() in _FOREIGN:
        return None  # a MELFA BASIC V statement (``Print(1) = …``): the parser says so
    read = read_expr(piece, m.end(), end, line)
    if read is None:
        return None
    value, after = read
    pulse = None
    if after != end:
        word, after = _word(piece, after, end)
        if word != "DLY":
            return None
        read = read_expr(piece, after, end, line)
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
    read = read_expr(piece, pos, end, line)
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
        read = read_expr(piece, after, end, line)
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
    read = read_expr(piece, pos, end, line)
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
        number = to_int(digits)
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
