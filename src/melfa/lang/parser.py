"""Error-recovering recursive-descent parser: text to `melfa.lang.ast.Program`.

`parse` never raises. Each text line is parsed on its own (MELFA BASIC IV has one statement
per step), so a broken line can never hide the lines after it. Inside a line the parser
resumes at the structural keywords THEN and ELSE: ``IF end < start THEN HOPEN`` reports the
bad condition *and* the HOPEN without a hand number. Otherwise the rest of the line becomes an
`InvalidStatement` and only the first mistake on it is reported (no cascades).

Expressions use precedence climbing over the reference's priority table (§2.4), highest
first: ``^``, unary ``+ -``, ``* /``, ``\\``, ``MOD``, binary ``+ -``, ``<< >>``, comparisons,
``NOT``, ``AND``, ``OR``, ``XOR``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from operator import itemgetter
from typing import Final

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.lexer import tokenize
from melfa.lang.model import V_DEF_TYPES, Construct, foreign_constructs
from melfa.lang.tokens import ELEMENTS, FUNCTIONS, KEYWORDS, STATEMENT_KEYWORDS, Token, TokenKind
from melfa.lang.typos import suggest


class K:
    """TokenKind members as plain class attributes: `TokenKind.X` costs ~60 ns on 3.11
    (enum descriptor), a class attribute ~15 ns, and the parser reads kinds constantly."""

    LINE_NUMBER: Final = TokenKind.LINE_NUMBER
    KEYWORD: Final = TokenKind.KEYWORD
    IDENT: Final = TokenKind.IDENT
    LABEL: Final = TokenKind.LABEL
    INTEGER: Final = TokenKind.INTEGER
    REAL: Final = TokenKind.REAL
    HEX: Final = TokenKind.HEX
    BIN: Final = TokenKind.BIN
    STRING: Final = TokenKind.STRING
    OP: Final = TokenKind.OP
    COMMA: Final = TokenKind.COMMA
    LPAREN: Final = TokenKind.LPAREN
    RPAREN: Final = TokenKind.RPAREN
    DOT_ELEMENT: Final = TokenKind.DOT_ELEMENT
    COMMENT: Final = TokenKind.COMMENT
    NEWLINE: Final = TokenKind.NEWLINE
    EOF: Final = TokenKind.EOF
    ERROR: Final = TokenKind.ERROR


_END_KINDS = frozenset({K.NEWLINE, K.EOF})
# Enum members by value: a dict lookup is many times cheaper than calling the Enum class.
_ELEMENT_KINDS = {k.value: k for k in A.ElementKind}
_MOVE_KINDS = {k.value: k for k in A.MoveKind}
_SWITCH_KINDS = {k.value: k for k in A.SwitchKind}
_WORD_KINDS = frozenset({K.KEYWORD, K.IDENT})

# Binary operator -> (precedence, BinaryOp); higher binds tighter. §2.4.
_BINARY: dict[str, tuple[int, A.BinaryOp]] = {
    "XOR": (1, A.BinaryOp.XOR),
    "OR": (2, A.BinaryOp.OR),
    "AND": (3, A.BinaryOp.AND),
    # 4: NOT (prefix)
    "=": (5, A.BinaryOp.EQ),
    "<>": (5, A.BinaryOp.NE),
    "><": (5, A.BinaryOp.NE),
    "<": (5, A.BinaryOp.LT),
    "<=": (5, A.BinaryOp.LE),
    "=<": (5, A.BinaryOp.LE),
    ">": (5, A.BinaryOp.GT),
    ">=": (5, A.BinaryOp.GE),
    "=>": (5, A.BinaryOp.GE),
    "<<": (6, A.BinaryOp.SHL),
    ">>": (6, A.BinaryOp.SHR),
    "+": (7, A.BinaryOp.ADD),
    "-": (7, A.BinaryOp.SUB),
    "MOD": (8, A.BinaryOp.MOD),
    "\\": (9, A.BinaryOp.IDIV),
    "*": (10, A.BinaryOp.MUL),
    "/": (10, A.BinaryOp.DIV),
    # 11: unary + -
    "^": (12, A.BinaryOp.POW),
}
# Builds a Span from a tuple without NamedTuple.__new__ (half the cost; a Span per node).
_new_tuple = tuple.__new__
_PREC_NOT_OPERAND = 5
MAX_EXPR_DEPTH = 64  # nested operators/parentheses; far beyond a 127-character step
_PREC_UNARY_OPERAND = 12

_DEF_TYPES = {t.value: t for t in A.VarType}
_DEF_WORDS = (*_DEF_TYPES, "IO", "PLT", "ACT", "ARCH", "FN")
_IO_TYPES = {t.value: t for t in A.IOType}

# Statements that are a keyword and a plain argument list: (min args, max args, empties ok).
_COMMANDS: dict[str, tuple[A.CommandKind, int, int, bool]] = {
    "OVRD": (A.CommandKind.OVRD, 1, 3, False),
    "JOVRD": (A.CommandKind.JOVRD, 1, 1, False),
    "SPD": (A.CommandKind.SPD, 1, 1, False),
    "ACCEL": (A.CommandKind.ACCEL, 0, 6, True),
    "CNT": (A.CommandKind.CNT, 1, 3, True),
    "FINE": (A.CommandKind.FINE, 1, 2, False),
    "LOADSET": (A.CommandKind.LOADSET, 2, 2, False),
    "TORQ": (A.CommandKind.TORQ, 2, 2, False),
    "JRC": (A.CommandKind.JRC, 1, 2, False),
    "HOPEN": (A.CommandKind.HOPEN, 1, 4, False),
    "HCLOSE": (A.CommandKind.HCLOSE, 1, 4, False),
    "TOOL": (A.CommandKind.TOOL, 1, 1, False),
    "BASE": (A.CommandKind.BASE, 1, 1, False),
    "HLT": (A.CommandKind.HLT, 0, 0, False),
    "DLY": (A.CommandKind.DLY, 1, 1, False),
    "ERROR": (A.CommandKind.ERROR, 1, 1, False),
    "SKIP": (A.CommandKind.SKIP, 0, 0, False),
    "CALLP": (A.CommandKind.CALLP, 1, 17, False),
    "XLOAD": (A.CommandKind.XLOAD, 2, 2, False),
    "XRUN": (A.CommandKind.XRUN, 1, 3, False),
    "XSTP": (A.CommandKind.XSTP, 1, 1, False),
    "XRST": (A.CommandKind.XRST, 1, 1, False),
    "XCLR": (A.CommandKind.XCLR, 1, 1, False),
    "PRIORITY": (A.CommandKind.PRIORITY, 1, 2, False),
    "GETM": (A.CommandKind.GETM, 1, 1, False),
    # Plain RELM releases the mechanism: the reference's GETM example ends `60 RELM`
    # [S1 RELM, GETM].
    "RELM": (A.CommandKind.RELM, 0, 1, False),
    "CMPG": (A.CommandKind.CMPG, 1, 8, True),
    "CLR": (A.CommandKind.CLR, 1, 1, False),
    "CHRSRCH": (A.CommandKind.CHRSRCH, 2, 4, False),
}

_ARC_KINDS = {k.value: k for k in A.ArcKind}

# One example each, for "Add a value after OVRD, e.g. OVRD 50." (missing-argument).
_COMMAND_EXAMPLES: dict[str, str] = {
    "OVRD": "OVRD 50",
    "JOVRD": "JOVRD 50",
    "SPD": "SPD 100",
    "CNT": "CNT 1",
    "FINE": "FINE 100",
    "LOADSET": "LOADSET 1, 1",
    "TORQ": "TORQ 4, 10",
    "JRC": "JRC 1",
    "HOPEN": "HOPEN 1",
    "HCLOSE": "HCLOSE 1",
    "TOOL": "TOOL (0, 0, 100, 0, 0, 0)",
    "BASE": "BASE P_NBASE",
    "DLY": "DLY 0.5",
    "ERROR": "ERROR 9100",
    "CALLP": 'CALLP "P10"',
    "XLOAD": 'XLOAD 2, "P1"',
    "XRUN": 'XRUN 2, "P1"',
    "XSTP": "XSTP 2",
    "XRST": "XRST 2",
    "XCLR": "XCLR 2",
    "PRIORITY": "PRIORITY 1",
    "GETM": "GETM 1",
    "CLR": "CLR 1",
}
# Words that continue a statement: finding one where a value should be means the value is
# missing (``IF M1 = THEN``), not that a reserved word was used as a name.
_CLAUSE_WORDS = frozenset(
    {"THEN", "ELSE", "TO", "STEP", "IS", "TYPE", "WTH", "WTHIF", "AND", "OR", "XOR", "MOD"}
    | {"AS", "GOTO", "GOSUB", "DLY"}
)
_PLT_HINT = "Give the 8 values, e.g. DEF PLT 1, P1, P2, P3, , 4, 3, 1 (diagonal left out)."


def _rename_hint(word: str) -> str:
    """Reserved words cannot be names; IV numbers start with M, so offer M + the word."""
    return f"Choose another name, e.g. M{word}."


class _Fail(Exception):
    """Unwinds to the nearest recovery point; carries the issue already recorded."""

    def __init__(self, issue: A.ParseIssue) -> None:
        super().__init__(issue.message)
        self.issue = issue


def _to_int(text: str, base: int = 10) -> int:
    # Absurdly long literals would hit Python's int-from-str digit limit; they are
    # out of every controller range anyway.
    return int(text, base) if len(text) <= 40 else 10**40


def step_number(digits: str) -> int:
    """The value of a step number's digits, as `parse` reads it (`melfa.lang.reparse`)."""
    return _to_int(digits)


def _describe(tok: Token) -> str:
    if tok.kind in _END_KINDS:
        return "the end of the line"
    if tok.kind is K.ERROR:
        return f"the character {tok.text[:1]!r}"
    return tok.text if len(tok.text) <= 20 else tok.text[:20] + "…"


class _LineParser:
    """Parses the tokens of one line (NEWLINE/EOF last, comments removed)."""

    def __init__(self, toks: list[Token], labels: Labels) -> None:
        self.toks = toks
        self.i = 0
        self.issues: list[A.ParseIssue] = []
        self.labels = labels  # labels jumped to anywhere in the file (for bare-word hints)
        self.depth = 0  # expression nesting, bounded so deep input cannot exhaust the stack

    def reset(self, toks: list[Token]) -> None:
        """Ready for another line (cheaper than a new parser per line)."""
        self.toks = toks
        self.i = 0
        self.issues = []
        self.depth = 0

    # ------------------------------------------------------------------ token helpers

    def peek(self, k: int = 0) -> Token:
        j = self.i + k
        toks = self.toks
        return toks[j] if j < len(toks) else toks[-1]

    def advance(self) -> Token:
        tok = self.toks[self.i]
        if tok.kind not in _END_KINDS:
            self.i += 1
        return tok

    def at_end(self) -> bool:
        return self.toks[self.i].kind in _END_KINDS

    def at_word(self, word: str) -> bool:
        tok = self.toks[self.i]
        return tok.kind in _WORD_KINDS and tok.text.upper() == word

    def at_op(self, op: str) -> bool:
        tok = self.toks[self.i]
        return tok.kind is K.OP and tok.text == op

    def at_kind(self, kind: TokenKind) -> bool:
        return self.toks[self.i].kind is kind

    def last_span(self, start: Token) -> A.Span:
        """From `start` to the last consumed token."""
        last = self.toks[self.i - 1] if self.i > 0 else start
        if last.column < start.column:
            last = start
        return _new_tuple(A.Span, (start.line, start.column, last.line, last.end_column))

    @staticmethod
    def tok_span(tok: Token) -> A.Span:
        if tok.kind is K.NEWLINE or tok.kind is K.EOF:
            return A.Span(tok.line, tok.column, tok.line, tok.column)
        # Fields 2..5 of a token are exactly (line, column, end_line, end_column).
        return _new_tuple(A.Span, tok[2:6])

    def issue(
        self,
        tok: Token,
        message: str,
        rule: str = "syntax-error",
        suggestion: str | None = None,
        code: str | None = "L4220",
        replacement: str | None = None,
    ) -> A.ParseIssue:
        span = self.tok_span(tok)
        if tok.kind in _END_KINDS and self.i > 0:
            # "missing …" at the end of a line: point at the last token written.
            prev = self.toks[self.i - 1]
            span = A.Span(prev.line, prev.column, prev.line, prev.end_column)
        found = A.ParseIssue(span, message, rule, code, suggestion, replacement)
        self.issues.append(found)
        return found

    def fail(
        self,
        tok: Token,
        message: str,
        rule: str = "syntax-error",
        suggestion: str | None = None,
        code: str | None = "L4220",
        replacement: str | None = None,
    ) -> _Fail:
        if tok.kind is K.ERROR:
            replacement = None
            if tok.text.startswith('"'):
                message, rule = "String is not closed", "unclosed-string"
                suggestion = 'Add the closing " before the end of the line.'
            elif tok.text == "_" and (word := self.word_after(tok)):
                message = f"A name cannot start with '_' (_{word})"
                rule, code = "name-starts-with-underscore", "L4310"
                suggestion = f"Start the name with a letter, e.g. M{word}; '_' may come later."
            else:
                message = f"Character {tok.text!r} is not part of MELFA BASIC IV"
                rule, code = "illegal-character", "L4310"
                suggestion = "Remove it, or move it into a string or a comment."
        return _Fail(self.issue(tok, message, rule, suggestion, code, replacement))

    def word_after(self, tok: Token) -> str:
        """The word glued to the right of `tok` (no space between), or ""."""
        for k in range(len(self.toks) - 1):
            if self.toks[k] is tok:
                nxt = self.toks[k + 1]
                return nxt.text if nxt.kind in _WORD_KINDS and not nxt.prefix else ""
        return ""

    def missing(self, what: str, context: str) -> _Fail:
        """`what` was expected at the current token (generic "Expected …" message)."""
        tok = self.peek()
        verb = "Add" if tok.kind in _END_KINDS else "Write"
        return self.fail(
            tok, f"Expected {what} {context}, found {_describe(tok)}", "syntax-error",
            f"{verb} {what} {context}.",
        )  # fmt: skip

    def expect_word(self, word: str, context: str) -> Token:
        if self.at_word(word):
            return self.advance()
        raise self.missing(word, context)

    def expect_kind(self, kind: TokenKind, what: str, context: str) -> Token:
        if self.toks[self.i].kind is kind:
            return self.advance()
        raise self.missing(what, context)

    def expect_op(self, op: str, context: str) -> Token:
        if self.at_op(op):
            return self.advance()
        raise self.missing(f"'{op}'", context)

    # --------------------------------------------------------------------- expressions

    def expr(self, min_prec: int = 0) -> A.Expr:
        tok = self.toks[self.i]
        kind = tok.kind
        self.depth += 1
        if self.depth > MAX_EXPR_DEPTH:
            raise self.fail(
                tok,
                "Expression is nested too deeply",
                suggestion="Split it into steps with intermediate variables.",
            )
        left: A.Expr
        if kind is K.OP and (tok.text == "-" or tok.text == "+"):
            self.i += 1
            operand = self.expr(_PREC_UNARY_OPERAND)
            op = A.UnaryOp.MINUS if tok.text == "-" else A.UnaryOp.PLUS
            left = A.Unary(op, operand, self.last_span(tok))
        elif kind is K.KEYWORD and tok.text.upper() == "NOT":
            self.i += 1
            operand = self.expr(_PREC_NOT_OPERAND)
            left = A.Unary(A.UnaryOp.NOT, operand, self.last_span(tok))
        else:
            left = self.primary()
            if self.toks[self.i].kind is K.DOT_ELEMENT:  # `P1.X` (most values have no dot)
                left = self.postfix(left)
        binary = _BINARY
        while True:
            tok = self.toks[self.i]
            if tok.kind is K.OP:
                entry = binary.get(tok.text)
            elif tok.kind is K.KEYWORD:
                entry = binary.get(tok.text.upper())
            else:
                break
            if entry is None or entry[0] < min_prec:
                break
            prec, op2 = entry
            self.i += 1
            right = self.expr(prec + 1)
            start = left.span
            end = right.span
            left = A.Binary(
                op2,
                left,
                right,
                _new_tuple(A.Span, (start.line, start.column, end.end_line, end.end_column)),
                tok.text.upper(),
            )
        self.depth -= 1
        return left

    def postfix(self, base: A.Expr) -> A.Expr:
        while self.toks[self.i].kind is K.DOT_ELEMENT:
            tok = self.advance()
            name = tok.text[1:].upper()
            try:
                element = _ELEMENT_KINDS[name]
            except KeyError:
                guess = suggest(name, ELEMENTS) if len(name) > 1 else None
                raise self.fail(
                    tok,
                    f"Unknown element {tok.text}",
                    "unknown-element",
                    f"Write .{guess} instead of {tok.text}."
                    if guess
                    else "Use .X .Y .Z .A .B .C .L1 .L2 .FL1 .FL2 or .J1 to .J8.",
                    replacement=f".{guess}" if guess else None,
                ) from None
            s = base.span
            base = A.Element(
                base, element, _new_tuple(A.Span, (s.line, s.column, tok.line, tok.end_column))
            )
        return base

    def args(self, close_context: str) -> tuple[A.Expr, ...]:
        """After '(' : expressions separated by commas, then ')'."""
        items: list[A.Expr] = []
        if self.at_kind(K.RPAREN):
            self.advance()
            return ()
        while True:
            items.append(self.expr())
            if self.at_kind(K.COMMA):
                self.advance()
                continue
            self.expect_kind(K.RPAREN, "')'", close_context)
            return tuple(items)

    def primary(self) -> A.Expr:
        # A value's token is never the end of the line, so its span is fields 2..5 of it.
        tok = self.toks[self.i]
        kind = tok.kind
        if kind is K.INTEGER or kind is K.LINE_NUMBER:
            self.i += 1
            return A.Number(
                _to_int(tok.text), A.NumberKind.INTEGER, tok.text, _new_tuple(A.Span, tok[2:6])
            )
        if kind is K.REAL:
            self.i += 1
            text = tok.text
            if text[-1] == "#":
                text = self.double_suffix(tok)
            return A.Number(float(text), A.NumberKind.REAL, tok.text, _new_tuple(A.Span, tok[2:6]))
        if kind is K.HEX or kind is K.BIN:
            self.i += 1
            nk = A.NumberKind.HEX if kind is K.HEX else A.NumberKind.BIN
            value = _to_int(tok.text[2:], 16 if kind is K.HEX else 2)
            return A.Number(value, nk, tok.text, _new_tuple(A.Span, tok[2:6]))
        if kind is K.STRING:
            self.i += 1
            return A.String(tok.text[1:-1], _new_tuple(A.Span, tok[2:6]))
        if kind is K.IDENT:
            self.i += 1
            name = A.Name(tok.text.upper(), _new_tuple(A.Span, tok[2:6]), tok.text)
            if self.toks[self.i].kind is K.LPAREN:
                self.i += 1
                args = self.args(f"to close {tok.text}(")
                if name.name.startswith("FN"):
                    return A.Call(name.name, args, True, self.last_span(tok))
                return A.Index(name, args, self.last_span(tok))
            return name
        after = self.toks[self.i - 1].text if self.i > 0 else ""
        if kind is K.KEYWORD:
            word = tok.text.upper()
            if word in FUNCTIONS:
                self.i += 1
                self.expect_kind(K.LPAREN, "'('", f"after the function {word}")
                args = self.args(f"to close {word}(")
                return A.Call(word, args, False, self.last_span(tok))
            if word == "PLT":
                raise self.fail(
                    tok,
                    "PLT needs parentheses here: only an assignment's value may be a bare PLT",
                    suggestion="Write it in parentheses, e.g. MOV (PLT 1, 5).",
                )
            if word in _CLAUSE_WORDS and after:
                raise self.fail(
                    tok,
                    f"Expected a value before {word}",
                    "expected-expression",
                    f"Write a value after {after}.",
                )
            raise self.fail(
                tok,
                f"{word} is a reserved word and cannot be used as a value here",
                "reserved-word",
                _rename_hint(word),
            )
        if kind is K.LPAREN:
            return self.paren()
        raise self.fail(
            tok,
            f"Expected a value, found {_describe(tok)}",
            "expected-expression",
            f"Write a number, a variable or an expression after {after}." if after else None,
        )

    def double_suffix(self, tok: Token) -> str:
        """``1.0#``: V's double-precision suffix, explained once; the number without it."""
        text = tok.text[:-1]
        self.issue(
            tok,
            f"The # of {tok.text} marks a double-precision constant in MELFA BASIC V; "
            "MELFA BASIC IV numbers have no type suffix",
            "melfa-basic-v",
            f"Write {text} (a variable declared with DEF DOUBLE holds it in double precision).",
        )
        return text

    def bare_pallet(self) -> A.Pallet:
        """``PLACE = PLT 1, M1``: as an assignment's value PLT needs no parentheses (§4.1)."""
        start = self.advance()  # PLT
        pallet = self.expr()
        self.expect_kind(K.COMMA, "','", "between the pallet and the grid number")
        index = self.expr()
        return A.Pallet(pallet, index, self.last_span(start))

    def comma_list(self, close_context: str) -> tuple[list[A.Expr | None], int]:
        """After '(' : a list whose elements may be omitted, then ')'. Returns (items, commas)."""
        items: list[A.Expr | None] = []
        commas = 0
        while True:
            tok = self.toks[self.i]
            if tok.kind is K.COMMA or tok.kind is K.RPAREN:
                items.append(None)
            else:
                items.append(self.expr())
            if self.at_kind(K.COMMA):
                self.advance()
                commas += 1
                continue
            self.expect_kind(K.RPAREN, "')'", close_context)
            return items, commas

    def paren(self) -> A.Expr:
        start = self.advance()  # (
        if self.at_word("PLT"):
            self.advance()
            pallet = self.expr()
            self.expect_kind(K.COMMA, "','", "between the pallet and the grid number")
            index = self.expr()
            self.expect_kind(K.RPAREN, "')'", "to close (PLT")
            return A.Pallet(pallet, index, self.last_span(start))
        items, commas = self.comma_list("to close '('")
        if commas == 0:
            inner = items[0]
            if inner is None:
                raise self.fail(
                    start,
                    "Empty parentheses",
                    suggestion="Write a value or a position constant inside them.",
                )
            return inner
        flags: tuple[A.Expr | None, ...] | None = None
        if self.at_kind(K.LPAREN):
            self.advance()
            flag_items, _ = self.comma_list("to close the structure flags (FL1,FL2)")
            flags = tuple(flag_items)
        return A.PositionLiteral(tuple(items), flags, self.last_span(start))

    # -------------------------------------------------------------------- jump targets

    def target(self, context: str) -> A.JumpTarget:
        tok = self.toks[self.i]
        if tok.kind is K.LABEL:
            self.i += 1
            return A.LabelRef(tok.text[1:].upper(), _new_tuple(A.Span, tok[2:6]), tok.text[1:])
        if tok.kind is K.INTEGER:
            self.i += 1
            return A.LineRef(_to_int(tok.text), _new_tuple(A.Span, tok[2:6]))
        if tok.kind is K.IDENT:
            raise self.fail(
                tok,
                f"Label needs to start with * ({tok.text})",
                "label-without-star",
                f"Write *{tok.text} to jump to the label.",
                replacement=f"*{tok.text}",
            )
        raise self.fail(
            tok,
            f"Expected a line number or *label {context}, found {_describe(tok)}",
            suggestion=f"Write a *label or a step number {context}.".replace(" .", "."),
        )

    # ---------------------------------------------------------------------- statements

    def statement(self, stop: frozenset[str] = frozenset()) -> A.Statement:
        """Parse one statement; on error, skip to a `stop` word or the end of the line."""
        start_i = self.i
        start = self.toks[self.i]
        self.depth = 0
        try:
            return self.statement_inner()
        except _Fail as failure:
            toks = self.toks
            i = max(self.i, start_i)
            while toks[i].kind not in _END_KINDS and not (
                toks[i].kind is K.KEYWORD and toks[i].text.upper() in stop and i > start_i
            ):
                i += 1
            self.i = i
            last = toks[i - 1] if i > start_i else start
            text = "".join(t.prefix + t.text for t in toks[start_i:i]).lstrip()
            span = A.Span(start.line, start.column, last.line, max(last.end_column, start.column))
            return A.InvalidStatement(text, failure.issue, span)

    def statement_inner(self) -> A.Statement:
        tok = self.toks[self.i]
        if tok.kind is K.KEYWORD:
            word = tok.text.upper()
            nxt = self.peek(1)
            if nxt.kind is K.OP and nxt.text == "=":
                kind = "a built-in function" if word in FUNCTIONS else "a reserved word"
                raise self.fail(
                    tok,
                    f"{word} is {kind} and cannot be assigned",
                    "reserved-word",
                    _rename_hint(word),
                )
            method = _DISPATCH.get(word)
            if method is not None:
                self.i += 1
                return method(self, tok)
            command = _COMMANDS.get(word)
            if command is not None:
                self.i += 1
                return self.command(tok, *command)
            raise self.fail(tok, f"{word} cannot start a statement", "invalid-statement")
        if tok.kind is K.IDENT:
            return self.assignment_or_typo(tok)
        if tok.kind is K.LABEL:
            raise self.fail(
                tok,
                "A label must be the first thing on its line (after the step number)",
                suggestion=f"Move {tok.text} to the start of the line, or write GOTO {tok.text}.",
            )
        raise self.fail(tok, f"Expected a statement, found {_describe(tok)}", "invalid-statement")

    def assignment_or_typo(self, tok: Token) -> A.Statement:
        nxt = self.peek(1)
        if not (nxt.kind is K.OP and nxt.text == "="):
            self.foreign(tok)
        if not (nxt.kind is K.OP and nxt.text == "=") and nxt.kind not in (
            K.LPAREN,
            K.DOT_ELEMENT,
        ):
            word = tok.text.upper()
            guess = suggest(word, STATEMENT_KEYWORDS)
            if guess is not None:
                raise self.fail(
                    tok,
                    f"{tok.text} is not a MELFA BASIC IV word: did you mean {guess}?",
                    "unknown-statement",
                    f"Replace with {guess}.",
                    replacement=guess,
                )
            if nxt.kind in _END_KINDS and word in self.labels:
                raise self.fail(
                    tok,
                    f"Label needs to start with * ({tok.text})",
                    "label-without-star",
                    f"Write *{tok.text} to define the label.",
                    replacement=f"*{tok.text}",
                )
            raise self.fail(
                nxt if nxt.kind not in _END_KINDS else tok,
                f"Invalid statement: expected '=' after {tok.text} (assignment), "
                f"found {_describe(nxt)}",
                "unknown-statement",
            )
        target = self.assign_target()
        return self.assignment_rest(target, tok)

    def foreign(self, tok: Token) -> None:
        """A statement of MELFA BASIC V (ElseIf, Const, Fsc…): one message that says so and
        how to write it in IV, instead of a typo guess that would change the meaning."""
        construct = foreign_constructs().get(tok.text.upper())
        if construct is None:
            return
        raise self.v_construct(tok, construct)

    def v_construct(self, tok: Token, construct: Construct) -> _Fail:
        """The one finding for a MELFA BASIC V construct: what it is, the IV way or none."""
        return self.fail(
            tok,
            f"{construct.what} is MELFA BASIC V; the CR2B-574 runs MELFA BASIC IV, "
            "which does not have it",
            "melfa-basic-v",
            construct.in_iv
            or "Not available in IV: MELFA BASIC IV has no equivalent, so remove the line.",
        )

    def assign_target(self) -> A.AssignTarget:
        tok = self.toks[self.i]
        if tok.kind is not K.IDENT:
            if tok.kind is K.KEYWORD:
                raise self.fail(
                    tok,
                    f"{tok.text.upper()} is a reserved word and cannot be a variable",
                    "reserved-word",
                    _rename_hint(tok.text.upper()),
                )
            raise self.fail(tok, f"Expected a variable, found {_describe(tok)}")
        self.i += 1
        name = A.Name(tok.text.upper(), _new_tuple(A.Span, tok[2:6]), tok.text)
        target: A.AssignTarget = name
        if self.at_kind(K.LPAREN):
            self.advance()
            target = A.Index(name, self.args(f"to close {tok.text}("), self.last_span(tok))
        if self.at_kind(K.DOT_ELEMENT):
            element = self.postfix(target)
            assert isinstance(element, A.Element)
            target = element
        return target

    def assignment_rest(self, target: A.AssignTarget, start: Token) -> A.Assign:
        self.expect_op("=", "in the assignment")
        value = self.bare_pallet() if self.at_word("PLT") else self.expr()
        pulse = None
        if self.at_word("DLY"):
            self.advance()
            pulse = self.expr()
        return A.Assign(target, value, pulse, self.last_span(start))

    def arg_list(self, allow_empty: bool) -> list[A.Expr | None]:
        items: list[A.Expr | None] = []
        if self.at_end() or self.at_word("ELSE"):
            return items
        while True:
            tok = self.toks[self.i]
            if allow_empty and (tok.kind is K.COMMA or tok.kind in _END_KINDS):
                items.append(None)
            else:
                items.append(self.expr())
            if self.at_kind(K.COMMA):
                self.advance()
                continue
            return items

    def command(
        self, tok: Token, kind: A.CommandKind, lo: int, hi: int, empties: bool
    ) -> A.Command:
        args = self.arg_list(empties)
        word = kind.value
        if len(args) < lo:
            what = "a value" if lo == 1 else f"{lo} values"
            if word in ("HOPEN", "HCLOSE"):
                what = "a hand number (1 to 8)"
            example = _COMMAND_EXAMPLES.get(word)
            raise self.fail(
                self.peek(),
                f"{word} needs {what}, found {_describe(self.peek())}",
                "missing-argument",
                f"Add {what} after {word}" + (f", e.g. {example}." if example else "."),
            )
        if len(args) > hi:
            values = f"{hi} value{'s' if hi != 1 else ''}"
            raise self.fail(
                tok,
                f"{word} takes at most {values}, found {len(args)}",
                "too-many-arguments",
                f"Remove the extra values: {word} takes at most {values}."
                if hi
                else f"Remove the values after {word}.",
            )
        return A.Command(kind, tuple(args), self.last_span(tok))

    # movement ---------------------------------------------------------------------

    def move_tail(self) -> tuple[A.MoveType | None, A.Appended | None]:
        if self.toks[self.i].kind in _END_KINDS:  # the usual case: nothing after the target
            return None, None
        mtype = None
        if self.at_word("TYPE"):
            t = self.advance()
            c1 = self.expr()
            c2 = None
            if self.at_kind(K.COMMA):
                self.advance()
                c2 = self.expr()
            mtype = A.MoveType(c1, c2, self.last_span(t))
        appended = None
        if self.at_word("WTH") or self.at_word("WTHIF"):
            t = self.advance()
            condition = None
            if t.text.upper() == "WTHIF":
                condition = self.expr()
                self.expect_kind(K.COMMA, "','", "after the WTHIF condition")
            action = self.appended_action()
            appended = A.Appended(condition, action, self.last_span(t))
        return mtype, appended

    def appended_action(self) -> A.Statement:
        tok = self.toks[self.i]
        if tok.kind is K.KEYWORD and tok.text.upper() in ("HLT", "SKIP"):
            self.i += 1
            kind = A.CommandKind.HLT if tok.text.upper() == "HLT" else A.CommandKind.SKIP
            return A.Command(kind, (), self.tok_span(tok))
        if tok.kind is K.IDENT:
            target = self.assign_target()
            return self.assignment_rest(target, tok)
        raise self.fail(
            tok,
            f"Expected an assignment, HLT or SKIP after WTH/WTHIF, found {_describe(tok)}",
            suggestion="Write what to do during the move, e.g. WTH M_OUT(17) = 1.",
        )

    def target_expr(self, word: str) -> A.Expr:
        if self.at_end():
            raise self.fail(
                self.peek(),
                f"{word} needs a target position",
                "missing-argument",
                f"Add the position to move to, e.g. {word} P1.",
            )
        return self.expr()

    def st_move(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        kind = _MOVE_KINDS[word]
        target: A.Expr | None = None
        close: A.Expr | None = None
        if kind is A.MoveKind.MVS and self.at_kind(K.COMMA):
            self.advance()
            close = self.expr()
        else:
            target = self.target_expr(word)
            if self.at_kind(K.COMMA):
                self.advance()
                close = self.expr()
        mtype, appended = self.move_tail()
        return A.Move(kind, target, close, mtype, appended, self.last_span(tok))

    def st_arc(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        points = [self.target_expr(word)]
        while self.at_kind(K.COMMA):
            self.advance()
            points.append(self.expr())
        if len(points) != 3:
            raise self.fail(
                tok,
                f"{word} needs 3 positions (start, {'via' if word != 'MVR3' else 'end'}, …), "
                f"found {len(points)}",
                "missing-argument" if len(points) < 3 else "too-many-arguments",
                f"Give {word} three positions, e.g. {word} P1, P2, P3.",
            )
        mtype, appended = self.move_tail()
        return A.ArcMove(_ARC_KINDS[word], tuple(points), mtype, appended, self.last_span(tok))

    def st_mva(self, tok: Token) -> A.Statement:
        target = self.target_expr("MVA")
        arch = None
        if self.at_kind(K.COMMA):
            self.advance()
            arch = self.expr()
        _, appended = self.move_tail()
        return A.ArchMove(target, arch, appended, self.last_span(tok))

    # switches -----------------------------------------------------------------------

    def on_off(self, word: str) -> bool:
        if self.at_word("ON"):
            self.advance()
            return True
        if self.at_word("OFF"):
            self.advance()
            return False
        raise self.fail(
            self.peek(),
            f"Expected ON or OFF after {word}, found {_describe(self.peek())}",
            suggestion=f"Write {word} ON or {word} OFF.",
        )

    def st_switch(self, tok: Token) -> A.Statement:
        word = tok.text.upper()
        on = self.on_off(word)
        extra: list[A.Expr] = []
        while self.at_kind(K.COMMA):
            self.advance()
            extra.append(self.expr())
        return A.Switch(_SWITCH_KINDS[word], on, tuple(extra), self.last_span(tok))

    def st_cmp(self, tok: Token) -> A.Statement:
        nxt = self.peek()
        mode_word = nxt.text.upper() if nxt.kind in _WORD_KINDS else ""
        if mode_word == "OFF":
            self.advance()
            return A.Cmp(A.CmpMode.OFF, None, self.last_span(tok))
        if mode_word not in ("JNT", "POS", "TOOL"):
            raise self.fail(
                nxt,
                f"Expected JNT, POS, TOOL or OFF after CMP, found {_describe(nxt)}",
                suggestion="Write CMP JNT, CMP POS or CMP TOOL with a mask, or CMP OFF.",
            )
        self.advance()
        self.expect_kind(K.COMMA, "','", f"after CMP {mode_word}")
        mask = self.expr()
        return A.Cmp(A.CmpMode(mode_word), mask, self.last_span(tok))

    # flow ----------------------------------------------------------------------------

    def st_goto(self, tok: Token) -> A.Statement:
        target = self.target(f"after {tok.text.upper()}")
        if tok.text.upper() == "GOTO":
            return A.Goto(target, self.last_span(tok))
        return A.Gosub(target, self.last_span(tok))

    def st_on(self, tok: Token) -> A.Statement:
        if self.at_word("COM"):
            self.advance()
            port = None
            if self.at_kind(K.LPAREN):
                self.advance()
                port = self.expr()
                self.expect_kind(K.RPAREN, "')'", "after ON COM(n")
            self.expect_word("GOSUB", "after ON COM")
            target = self.target("after ON COM … GOSUB")
            return A.OnCom(port, target, self.last_span(tok))
        selector = self.expr()
        if self.at_word("GOTO"):
            kind = A.JumpKind.GOTO
        elif self.at_word("GOSUB"):
            kind = A.JumpKind.GOSUB
        else:
            nxt = self.peek()
            raise self.fail(
                nxt,
                f"Expected GOTO or GOSUB after ON's value, found {_describe(nxt)}",
                suggestion="Write GOTO or GOSUB after the value, e.g. ON M1 GOTO *A, *B.",
            )
        self.advance()
        targets = [self.target(f"after ON … {kind.value}")]
        while self.at_kind(K.COMMA):
            self.advance()
            targets.append(self.target("in the ON list"))
        return A.OnJump(selector, kind, tuple(targets), self.last_span(tok))

    def st_return(self, tok: Token) -> A.Statement:
        mode = None if self.at_end() or self.at_word("ELSE") else self.expr()
        return A.Return(mode, self.last_span(tok))

    def branch(self, stop: frozenset[str]) -> A.JumpTarget | A.Statement:
        tok = self.toks[self.i]
        if tok.kind is K.INTEGER or tok.kind is K.LABEL:
            return self.target("")
        return self.statement(stop)

    def st_if(self, tok: Token) -> A.Statement:
        toks = self.toks
        cond_start = self.toks[self.i]
        condition: A.Expr
        try:
            if self.at_end() or self.at_word("THEN"):
                raise self.fail(
                    self.peek(),
                    "IF needs a condition",
                    "missing-argument",
                    "Add a condition, e.g. IF M1 = 1 THEN *LOOP.",
                )
            condition = self.expr()
        except _Fail as failure:
            self.depth = 0
            # Resume at THEN if the line has one; otherwise the whole IF is invalid.
            j = self.i
            while toks[j].kind not in _END_KINDS and not (
                toks[j].kind is K.KEYWORD and toks[j].text.upper() == "THEN"
            ):
                j += 1
            if toks[j].kind in _END_KINDS:
                raise
            self.i = j
            last = toks[j - 1] if j > 0 else cond_start
            condition = A.InvalidExpr(
                failure.issue,
                A.Span(cond_start.line, cond_start.column, last.line, last.end_column),
            )
        then: A.JumpTarget | A.Statement | None
        if self.at_word("THEN"):
            self.advance()
            if self.at_end():
                return A.If(condition, None, None, self.last_span(tok))
        else:
            nxt = self.peek()
            found = _describe(nxt)
            message = f"Expected THEN after IF condition and instead found {found}"
            cond_text = "".join(t.prefix + t.text for t in toks[toks.index(cond_start) : self.i])
            rest = " …" if nxt.kind in _END_KINDS else f" {nxt.text} …"
            hint = f"Add THEN after the condition: IF {cond_text.strip()} THEN{rest}"
            if not (
                nxt.kind is K.KEYWORD and nxt.text.upper() in STATEMENT_KEYWORDS
            ) and nxt.kind not in (K.INTEGER, K.LABEL):
                raise self.fail(nxt, message, "expected-then", hint, replacement="THEN")
            # The branch is readable: report the missing THEN and parse on.
            self.issue(nxt, message, "expected-then", hint, replacement="THEN")
        then = self.branch(frozenset({"ELSE"}))
        else_: A.JumpTarget | A.Statement | None = None
        if self.at_word("ELSE"):
            self.advance()
            if self.at_end():
                raise self.fail(
                    self.peek(),
                    "ELSE needs a line number, *label or statement",
                    suggestion="Add where to go after ELSE, e.g. ELSE *OTHER.",
                )
            else_ = self.branch(frozenset())
        return A.If(condition, then, else_, self.last_span(tok))

    def st_else(self, tok: Token) -> A.Statement:
        return A.Else(self.last_span(tok))

    def st_endif(self, tok: Token) -> A.Statement:
        return A.EndIf(self.last_span(tok))

    def name(self, context: str) -> A.Name:
        tok = self.toks[self.i]
        if tok.kind is K.IDENT:
            self.i += 1
            return A.Name(tok.text.upper(), self.tok_span(tok), tok.text)
        if tok.kind is K.KEYWORD:
            raise self.fail(
                tok,
                f"{tok.text.upper()} is a reserved word and cannot be a variable name",
                "reserved-word",
                _rename_hint(tok.text.upper()),
            )
        raise self.fail(tok, f"Expected a variable name {context}, found {_describe(tok)}")

    def st_for(self, tok: Token) -> A.Statement:
        counter = self.name("after FOR")
        self.expect_op("=", "after the FOR counter")
        start = self.expr()
        self.expect_word("TO", "after the FOR start value")
        end = self.expr()
        step = None
        if self.at_word("STEP"):
            self.advance()
            step = self.expr()
        return A.For(counter, start, end, step, self.last_span(tok))

    def st_next(self, tok: Token) -> A.Statement:
        counters: list[A.Name] = []
        if not self.at_end():
            counters.append(self.name("after NEXT"))
            while self.at_kind(K.COMMA):
                self.advance()
                counters.append(self.name("in the NEXT list"))
        return A.Next(tuple(counters), self.last_span(tok))

    def st_while(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "WHILE needs a condition",
                "missing-argument",
                "Add a condition, e.g. WHILE M1 < 10.",
            )
        return A.While(self.expr(), self.last_span(tok))

    def st_wend(self, tok: Token) -> A.Statement:
        return A.Wend(self.last_span(tok))

    def st_select(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "SELECT needs a value to compare",
                "missing-argument",
                "Add the value to compare, e.g. SELECT M1.",
            )
        return A.Select(self.expr(), self.last_span(tok))

    def st_case(self, tok: Token) -> A.Statement:
        if self.at_word("IS"):
            self.advance()
            op_tok = self.peek()
            entry = _BINARY.get(op_tok.text) if op_tok.kind is K.OP else None
            if entry is None or not entry[1].is_comparison:
                raise self.fail(
                    op_tok,
                    f"Expected a comparison after CASE IS, found {_describe(op_tok)}",
                    suggestion="Write a comparison after IS, e.g. CASE IS >= 3.",
                )
            self.advance()
            value = self.expr()
            return A.Case(A.CaseKind.IS, value, None, entry[1], self.last_span(tok))
        if self.at_end():
            raise self.fail(
                self.peek(), "CASE needs a value", "missing-argument", "Add a value, e.g. CASE 1."
            )
        value = self.expr()
        if self.at_word("TO"):
            self.advance()
            high = self.expr()
            return A.Case(A.CaseKind.RANGE, value, high, None, self.last_span(tok))
        return A.Case(A.CaseKind.VALUE, value, None, None, self.last_span(tok))

    def st_break(self, tok: Token) -> A.Statement:
        return A.Break(self.last_span(tok))

    def st_default(self, tok: Token) -> A.Statement:
        return A.Default(self.last_span(tok))

    def st_end(self, tok: Token) -> A.Statement:
        if self.at_word("SELECT"):
            self.advance()
            return A.EndSelect(self.last_span(tok))
        if self.at_word("IF"):
            raise self.fail(
                tok,
                "Invalid statement. Did you mean ENDIF instead of END IF?",
                "unknown-statement",
                "Write ENDIF as one word.",
                replacement="ENDIF",
            )
        return A.Command(A.CommandKind.END, (), self.last_span(tok))

    def st_wait(self, tok: Token) -> A.Statement:
        if self.at_end():
            raise self.fail(
                self.peek(),
                "WAIT needs a condition",
                "missing-argument",
                "Add a condition, e.g. WAIT M_IN(1) = 1.",
            )
        return A.Wait(self.expr(), self.last_span(tok))

    def st_fprm(self, tok: Token) -> A.Statement:
        params = [self.name("after FPRM")]
        while self.at_kind(K.COMMA):
            self.advance()
            params.append(self.name("in the FPRM list"))
        return A.Fprm(tuple(params), self.last_span(tok))

    def st_reset(self, tok: Token) -> A.Statement:
        self.expect_word("ERR", "after RESET")
        return A.Command(A.CommandKind.RESET_ERR, (), self.last_span(tok))

    # definitions -------------------------------------------------------------------------

    def st_def(self, tok: Token) -> A.Statement:
        kind_tok = self.peek()
        word = kind_tok.text.upper() if kind_tok.kind in _WORD_KINDS else ""
        if word in _DEF_TYPES:
            self.advance()
            names = [self.name(f"after DEF {word}")]
            while self.at_kind(K.COMMA):
                self.advance()
                names.append(self.name(f"in the DEF {word} list"))
            value = None
            if len(names) == 1 and self.at_op("="):
                self.advance()
                value = self.expr()
            return A.DefVar(_DEF_TYPES[word], tuple(names), value, self.last_span(tok))
        if word == "IO":
            self.advance()
            name = self.name("after DEF IO")
            self.expect_op("=", "after the DEF IO name")
            io_tok = self.peek()
            io_word = io_tok.text.upper() if io_tok.kind in _WORD_KINDS else ""
            if io_word not in _IO_TYPES:
                guess = suggest(io_word, _IO_TYPES) if io_word else None
                raise self.fail(
                    io_tok,
                    f"Expected BIT, BYTE, WORD, INTEGER or DWORD, found {_describe(io_tok)}",
                    suggestion=f"Write {guess} instead of {io_tok.text}."
                    if guess
                    else "Write the I/O type, e.g. DEF IO MSENSOR = BIT, 900.",
                    replacement=guess,
                )
            self.advance()
            self.expect_kind(K.COMMA, "','", "before the bit number")
            bit = self.expr()
            mask = None
            if self.at_kind(K.COMMA):
                self.advance()
                mask = self.expr()
            return A.DefIO(name, _IO_TYPES[io_word], bit, mask, self.last_span(tok))
        if word == "PLT":
            self.advance()
            items = self.arg_list(True)
            if len(items) != 8:
                raise self.fail(
                    tok,
                    "DEF PLT needs 8 values: number, start, end A, end B, [diagonal], "
                    f"count A, count B, direction (found {len(items)})",
                    "missing-argument" if len(items) < 8 else "too-many-arguments",
                    _PLT_HINT,
                )
            number, start, end_a, end_b, diag, count_a, count_b, direction = items
            if None in (number, start, end_a, end_b, count_a, count_b, direction):
                raise self.fail(
                    tok, "DEF PLT: only the diagonal point may be left out", suggestion=_PLT_HINT
                )
            assert number and start and end_a and end_b and count_a and count_b and direction
            return A.DefPlt(
                number,
                start,
                end_a,
                end_b,
                diag,
                count_a,
                count_b,
                direction,
                self.last_span(tok),
            )
        if word == "ACT":
            self.advance()
            priority = self.expr()
            self.expect_kind(K.COMMA, "','", "after the DEF ACT priority")
            condition = self.expr()
            if self.at_word("GOTO"):
                jkind = A.JumpKind.GOTO
            elif self.at_word("GOSUB"):
                jkind = A.JumpKind.GOSUB
            else:
                raise self.fail(
                    self.peek(),
                    f"Expected GOTO or GOSUB in DEF ACT, found {_describe(self.peek())}",
                    suggestion="Write GOTO or GOSUB before the target, "
                    "e.g. DEF ACT 1, M_IN(1) = 1 GOSUB *STOP.",
                )
            self.advance()
            target = self.target("in DEF ACT")
            mode = None
            if self.at_kind(K.COMMA):
                self.advance()
                mtok = self.peek()
                if mtok.kind is K.IDENT and mtok.text.upper() in ("S", "L"):
                    self.advance()
                    mode = mtok.text.upper()
                else:
                    raise self.fail(
                        mtok,
                        f"Expected S or L, found {_describe(mtok)}",
                        suggestion="Write S or L after the comma, or remove the comma.",
                    )
            return A.DefAct(priority, condition, jkind, target, mode, self.last_span(tok))
        if word == "ARCH":
            self.advance()
            items = self.arg_list(True)
            return A.Command(A.CommandKind.DEF_ARCH, tuple(items), self.last_span(tok))
        if kind_tok.kind is K.IDENT and word.startswith("FN") and len(word) > 2:
            self.advance()
            fname = A.Name(word, self.tok_span(kind_tok), kind_tok.text)
            params: list[A.Name] = []
            if self.at_kind(K.LPAREN):
                self.advance()
                if not self.at_kind(K.RPAREN):
                    params.append(self.name("in the DEF FN parameters"))
                    while self.at_kind(K.COMMA):
                        self.advance()
                        params.append(self.name("in the DEF FN parameters"))
                self.expect_kind(K.RPAREN, "')'", "after the DEF FN parameters")
            self.expect_op("=", "after the DEF FN name")
            body = self.expr()
            return A.DefFn(fname, tuple(params), body, self.last_span(tok))
        v_type = V_DEF_TYPES.get(word)
        if v_type is not None:
            raise self.v_construct(kind_tok, v_type)
        guess = suggest(word, _DEF_WORDS) if word else None
        if guess is not None:
            raise self.fail(
                kind_tok,
                f"Unknown DEF type {kind_tok.text}. Did you mean DEF {guess}?",
                "unknown-def-type",
                f"Replace with {guess}.",
                replacement=guess,
            )
        raise self.fail(
            kind_tok,
            "Expected a DEF type (INTE, FLOAT, DOUBLE, CHAR, POS, JNT, IO, PLT, ACT, ARCH or "
            f"FNname), found {_describe(kind_tok)}",
            "unknown-def-type",
            "Write the type after DEF, e.g. DEF INTE MCOUNT.",
        )

    def st_dim(self, tok: Token) -> A.Statement:
        arrays: list[A.DimArray] = []
        while True:
            start = self.peek()
            name = self.name("after DIM")
            self.expect_kind(K.LPAREN, "'('", f"after DIM {name.written}")
            sizes = self.args(f"to close DIM {name.written}(")
            if not sizes:
                raise self.fail(
                    start,
                    f"DIM {name.written}() needs 1 to 3 sizes",
                    suggestion=f"Write the size in the parentheses, e.g. DIM {name.written}(10).",
                )
            arrays.append(A.DimArray(name, sizes, self.last_span(start)))
            if not self.at_kind(K.COMMA):
                break
            self.advance()
        return A.Dim(tuple(arrays), self.last_span(tok))

    def st_act(self, tok: Token) -> A.Statement:
        number = self.expr(6)  # stop before '='
        self.expect_op("=", "after ACT n")
        value = self.expr()
        return A.ActSet(number, value, self.last_span(tok))

    # files and communication -----------------------------------------------------------

    def channel(self) -> A.Expr:
        if self.at_op("#"):
            self.advance()
        return self.expr()

    def st_open(self, tok: Token) -> A.Statement:
        file = self.expr()
        mode = None
        if self.at_word("FOR"):
            self.advance()
            mtok = self.peek()
            mword = mtok.text.upper() if mtok.kind in _WORD_KINDS else ""
            if mword not in ("INPUT", "OUTPUT", "APPEND"):
                raise self.fail(
                    mtok,
                    f"Expected INPUT, OUTPUT or APPEND, found {_describe(mtok)}",
                    suggestion="Write FOR INPUT, FOR OUTPUT or FOR APPEND.",
                )
            self.advance()
            mode = A.FileMode(mword)
        self.expect_word("AS", "in OPEN … AS #n")
        number = self.channel()
        return A.Open(file, mode, number, self.last_span(tok))

    def st_print(self, tok: Token) -> A.Statement:
        channel = None
        if self.at_op("#"):
            channel = self.channel()
            if not self.at_end():
                self.expect_kind(K.COMMA, "','", "after the PRINT channel")
        items: list[A.Expr] = []
        while not self.at_end():
            items.append(self.expr())
            if self.at_kind(K.COMMA) or self.at_op(";"):
                self.advance()
                continue
            break
        return A.Print(channel, tuple(items), self.last_span(tok))

    def st_input(self, tok: Token) -> A.Statement:
        channel = None
        if self.at_op("#"):
            channel = self.channel()
            self.expect_kind(K.COMMA, "','", "after the INPUT channel")
        targets = [self.assign_target()]
        while self.at_kind(K.COMMA):
            self.advance()
            targets.append(self.assign_target())
        return A.Input(channel, tuple(targets), self.last_span(tok))

    def st_close(self, tok: Token) -> A.Statement:
        channels: list[A.Expr] = []
        if not self.at_end():
            channels.append(self.channel())
            while self.at_kind(K.COMMA):
                self.advance()
                channels.append(self.channel())
        return A.Close(tuple(channels), self.last_span(tok))

    def st_com(self, tok: Token) -> A.Statement:
        port = None
        if self.at_kind(K.LPAREN):
            self.advance()
            port = self.expr()
            self.expect_kind(K.RPAREN, "')'", "after COM(n")
        stok = self.peek()
        sword = stok.text.upper() if stok.kind in _WORD_KINDS else ""
        if sword not in ("ON", "OFF", "STOP"):
            raise self.fail(
                stok,
                f"Expected ON, OFF or STOP after COM, found {_describe(stok)}",
                suggestion="Write COM ON, COM OFF or COM STOP.",
            )
        self.advance()
        return A.ComControl(port, A.ComState(sword), self.last_span(tok))


_DISPATCH = {
    "MOV": _LineParser.st_move,
    "MVS": _LineParser.st_move,
    "MVR": _LineParser.st_arc,
    "MVR2": _LineParser.st_arc,
    "MVR3": _LineParser.st_arc,
    "MVC": _LineParser.st_arc,
    "MVA": _LineParser.st_mva,
    "SERVO": _LineParser.st_switch,
    "PREC": _LineParser.st_switch,
    "OADL": _LineParser.st_switch,
    "CMP": _LineParser.st_cmp,
    "GOTO": _LineParser.st_goto,
    "GOSUB": _LineParser.st_goto,
    "ON": _LineParser.st_on,
    "RETURN": _LineParser.st_return,
    "IF": _LineParser.st_if,
    "ELSE": _LineParser.st_else,
    "ENDIF": _LineParser.st_endif,
    "FOR": _LineParser.st_for,
    "NEXT": _LineParser.st_next,
    "WHILE": _LineParser.st_while,
    "WEND": _LineParser.st_wend,
    "SELECT": _LineParser.st_select,
    "CASE": _LineParser.st_case,
    "BREAK": _LineParser.st_break,
    "DEFAULT": _LineParser.st_default,
    "END": _LineParser.st_end,
    "WAIT": _LineParser.st_wait,
    "FPRM": _LineParser.st_fprm,
    "RESET": _LineParser.st_reset,
    "DEF": _LineParser.st_def,
    "DIM": _LineParser.st_dim,
    "ACT": _LineParser.st_act,
    "OPEN": _LineParser.st_open,
    "PRINT": _LineParser.st_print,
    "INPUT": _LineParser.st_input,
    "CLOSE": _LineParser.st_close,
    "COM": _LineParser.st_com,
}

assert set(_DISPATCH) | set(_COMMANDS) | {"REM"} == STATEMENT_KEYWORDS
assert set(_BINARY) - {"MOD", "AND", "OR", "XOR"} <= {
    "=",
    "<>",
    "><",
    "<",
    "<=",
    "=<",
    ">",
    ">=",
    "=>",
    "<<",
    ">>",
    "+",
    "-",
    "\\",
    "*",
    "/",
    "^",
}
assert {"MOD", "AND", "OR", "XOR", "NOT"} <= KEYWORDS


class Labels:
    """The labels jumped to anywhere in the file, computed only if a line needs them."""

    def __init__(self, tokens: list[Token] | Callable[[], list[Token]]) -> None:
        self.tokens = tokens
        self.names: frozenset[str] | None = None
        self.asked = False
        """A line's parse asked (its result then depends on the rest of the file)."""

    def __contains__(self, name: object) -> bool:
        self.asked = True
        if self.names is None:
            tokens = self.tokens if isinstance(self.tokens, list) else self.tokens()
            self.names = frozenset(t.text[1:].upper() for t in tokens if t.kind is K.LABEL)
        return name in self.names


def parse_line(tokens: list[Token], labels: Labels, start: int = 0, end: int = -1) -> A.Line:
    """The tree of the line whose tokens are ``tokens[start:end + 1]`` (``end``: its NEWLINE
    or the EOF; -1: the first from ``start``); `labels` are the file's, asked only by a line
    with a mistake. A line lexed on its own is ``parse_line(tokenize(line, number), …)``."""
    if end < 0:
        end = next(k for k in range(start, len(tokens)) if tokens[k].kind in _END_KINDS)
    return _parse_line(tokens, start, end, _LineParser([], labels))


def parse_tokens(tokens: list[Token]) -> A.Program:
    """Build the tree from `tokenize` output (so callers that already lexed need not relex)."""
    return A.Program(tuple(line for line, _ in parse_lines(tokens, Labels(tokens))))


def parse_lines(tokens: list[Token], labels: Labels) -> Iterator[tuple[A.Line, bool]]:
    """The tree of each text line of `tokens`, and whether its parse asked `labels` (the
    file's: then the tree depends on more than the line, `melfa.lang.reparse`)."""
    parser = _LineParser([], labels)  # one for every line: see `_LineParser.reset`
    kinds = list(map(itemgetter(0), tokens))
    newline = K.NEWLINE
    i = 0
    last = len(tokens) - 1  # the EOF token
    while True:
        # One text line: tokens up to and including its NEWLINE (or the EOF).
        try:
            j = kinds.index(newline, i)
        except ValueError:
            j = last
        labels.asked = False
        yield _parse_line(tokens, i, j, parser), labels.asked
        if j == last:
            break
        i = j + 1


def _parse_line(tokens: list[Token], i: int, j: int, parser: _LineParser) -> A.Line:
    end_tok = tokens[j]
    lineno = end_tok.line
    span = _new_tuple(A.Span, (lineno, 1, lineno, end_tok.column))
    number = label = label_text = comment = None
    number_span = label_span = None
    k = i
    if k < j and tokens[k].kind is K.LINE_NUMBER:
        tok = tokens[k]
        number = _to_int(tok.text)
        number_span = _new_tuple(A.Span, (lineno, tok.column, lineno, tok.end_column))
        k += 1
    if k < j and tokens[k].kind is K.LABEL:
        tok = tokens[k]
        label_text = tok.text[1:]
        label = label_text.upper()
        label_span = _new_tuple(A.Span, (lineno, tok.column, lineno, tok.end_column))
        k += 1
    stop = j
    if stop > k and tokens[stop - 1].kind is K.COMMENT:
        text = tokens[stop - 1].text
        comment = text[1:] if text.startswith("'") else text[3:]
        stop -= 1
    if stop == k:
        return A.Line(number, label, None, span, comment, (), number_span, label_span, label_text)
    parser.reset([*tokens[k:stop], end_tok])
    statement = parser.statement()
    if not parser.at_end() and not isinstance(statement, A.InvalidStatement) and not parser.issues:
        extra = parser.peek()
        parser.fail(
            extra,
            f"Unexpected {_describe(extra)} after the end of the statement "
            "(one statement per line)",
            "unexpected-token",
            "Put each statement on a line of its own, or remove the extra text.",
        )
    return A.Line(
        number,
        label,
        statement,
        span,
        comment,
        tuple(parser.issues),
        number_span,
        label_span,
        label_text,
    )


def parse_constant(
    line: str, column: int
) -> tuple[A.PositionLiteral | None, A.ParseIssue | None, int]:
    """The position or joint constant ``(…)(fl1,fl2)`` starting at `column` (1-based) of a
    one-line text, read by the same code as constants inside programs (points files use it).

    Returns (constant, None, column after it) or (None, the syntax issue, 0). A single
    parenthesised value comes back as a one-element constant, so callers count elements.

    >>> lit, issue, end = parse_constant("Pa=(1,2,,4)(7,0) ' home", 4)
    >>> [e.value if e else None for e in lit.elements], len(lit.flags), end
    ([1, 2, None, 4], 2, 17)
    """
    toks = [tok for tok in tokenize(line) if tok.kind is not K.COMMENT]
    parser = _LineParser(toks, Labels(toks))
    while toks[parser.i].kind is not K.EOF and toks[parser.i].column < column:
        parser.i += 1
    start = toks[parser.i]
    try:
        if start.kind is not K.LPAREN:
            raise parser.fail(start, f"Expected '(', found {_describe(start)}")
        node = parser.paren()
    except _Fail as failure:
        return None, failure.issue, 0
    if not isinstance(node, A.PositionLiteral):
        node = A.PositionLiteral((node,), None, parser.last_span(start))
    return node, None, toks[parser.i - 1].end_column


def parse(text: str) -> A.Program:
    """Parse a whole program. Never raises; broken lines become `InvalidStatement` nodes.

    >>> program = parse("10 MOV P1, -50\\n20 HOPEN 1\\n")
    >>> [type(line.statement).__name__ for line in program.lines]
    ['Move', 'Command', 'NoneType']
    """
    return parse_tokens(tokenize(text))
