"""Expressions and the small pieces statements are made of: values by precedence climbing
over the reference's priority table (§2.4; highest first ``^``, unary ``+ -``, ``* /``,
``\\``, ``MOD``, binary ``+ -``, ``<< >>``, comparisons, ``NOT``, ``AND``, ``OR``, ``XOR``),
position constants and pallets, jump targets, variable names, assignment targets and
argument lists.

The hot path of the parser (`expr`, `primary`): local aliases and `new_tuple` spans keep it
cheap, as the checker parses on every keystroke. The statement families subclass
`ExprParser`.
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.grammar import BINARY
from melfa.lang.parse_cursor import (
    END_KINDS,
    Cursor,
    K,
    describe,
    new_tuple,
    rename_hint,
    to_int,
)
from melfa.lang.tokens import ELEMENTS, FUNCTIONS, Token
from melfa.lang.typos import suggest

# Enum members by value: a dict lookup is many times cheaper than calling the Enum class.
_ELEMENT_KINDS = {k.value: k for k in A.ElementKind}
_PREC_NOT_OPERAND = 5
MAX_EXPR_DEPTH = 64  # nested operators/parentheses; far beyond a 127-character step
_PREC_UNARY_OPERAND = 12
# Words that continue a statement: finding one where a value should be means the value is
# missing (``IF M1 = THEN``), not that a reserved word was used as a name.
_CLAUSE_WORDS = frozenset(
    {"THEN", "ELSE", "TO", "STEP", "IS", "TYPE", "WTH", "WTHIF", "AND", "OR", "XOR", "MOD"}
    | {"AS", "GOTO", "GOSUB", "DLY"}
)


class ExprParser(Cursor):
    """Reads values, jump targets, names and argument lists at the cursor."""

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
        binary = BINARY
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
                new_tuple(A.Span, (start.line, start.column, end.end_line, end.end_column)),
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
                base, element, new_tuple(A.Span, (s.line, s.column, tok.line, tok.end_column))
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
                to_int(tok.text), A.NumberKind.INTEGER, tok.text, new_tuple(A.Span, tok[2:6])
            )
        if kind is K.REAL:
            self.i += 1
            text = tok.text
            if text[-1] == "#":
                text = self.double_suffix(tok)
            return A.Number(float(text), A.NumberKind.REAL, tok.text, new_tuple(A.Span, tok[2:6]))
        if kind is K.HEX or kind is K.BIN:
            self.i += 1
            nk = A.NumberKind.HEX if kind is K.HEX else A.NumberKind.BIN
            value = to_int(tok.text[2:], 16 if kind is K.HEX else 2)
            return A.Number(value, nk, tok.text, new_tuple(A.Span, tok[2:6]))
        if kind is K.STRING:
            self.i += 1
            return A.String(tok.text[1:-1], new_tuple(A.Span, tok[2:6]))
        if kind is K.IDENT:
            self.i += 1
            name = A.Name(tok.text.upper(), new_tuple(A.Span, tok[2:6]), tok.text)
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
                rename_hint(word),
            )
        if kind is K.LPAREN:
            return self.paren()
        raise self.fail(
            tok,
            f"Expected a value, found {describe(tok)}",
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
            return A.LabelRef(tok.text[1:].upper(), new_tuple(A.Span, tok[2:6]), tok.text[1:])
        if tok.kind is K.INTEGER:
            self.i += 1
            return A.LineRef(to_int(tok.text), new_tuple(A.Span, tok[2:6]))
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
            f"Expected a line number or *label {context}, found {describe(tok)}",
            suggestion=f"Write a *label or a step number {context}.".replace(" .", "."),
        )

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
                rename_hint(tok.text.upper()),
            )
        raise self.fail(tok, f"Expected a variable name {context}, found {describe(tok)}")

    def assign_target(self) -> A.AssignTarget:
        tok = self.toks[self.i]
        if tok.kind is not K.IDENT:
            if tok.kind is K.KEYWORD:
                raise self.fail(
                    tok,
                    f"{tok.text.upper()} is a reserved word and cannot be a variable",
                    "reserved-word",
                    rename_hint(tok.text.upper()),
                )
            raise self.fail(tok, f"Expected a variable, found {describe(tok)}")
        self.i += 1
        name = A.Name(tok.text.upper(), new_tuple(A.Span, tok[2:6]), tok.text)
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
            if allow_empty and (tok.kind is K.COMMA or tok.kind in END_KINDS):
                items.append(None)
            else:
                items.append(self.expr())
            if self.at_kind(K.COMMA):
                self.advance()
                continue
            return items
