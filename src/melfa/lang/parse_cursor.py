"""The parser's reading position in one line's tokens, and how it reports a mistake.

`Cursor` is the base of the line parser (`melfa.lang.parser`): it peeks, advances and expects
tokens, builds spans, records `ParseIssue`s and raises `Fail` to unwind to the nearest
recovery point. The statement families (`parse_expr`, `parse_motion`, `parse_flow`,
`parse_defs`, `parse_io`) all read tokens through it; `Labels` are the file's labels a line's
message may name.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.model import Construct
from melfa.lang.tokens import Token, TokenKind


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


END_KINDS = frozenset({K.NEWLINE, K.EOF})
WORD_KINDS = frozenset({K.KEYWORD, K.IDENT})
# Builds a Span from a tuple without NamedTuple.__new__ (half the cost; a Span per node).
new_tuple = tuple.__new__


def rename_hint(word: str) -> str:
    """Reserved words cannot be names; IV numbers start with M, so offer M + the word."""
    return f"Choose another name, e.g. M{word}."


class Fail(Exception):
    """Unwinds to the nearest recovery point; carries the issue already recorded."""

    def __init__(self, issue: A.ParseIssue) -> None:
        super().__init__(issue.message)
        self.issue = issue


def to_int(text: str, base: int = 10) -> int:
    # Absurdly long literals would hit Python's int-from-str digit limit; they are
    # out of every controller range anyway.
    return int(text, base) if len(text) <= 40 else 10**40


def describe(tok: Token) -> str:
    if tok.kind in END_KINDS:
        return "the end of the line"
    if tok.kind is K.ERROR:
        return f"the character {tok.text[:1]!r}"
    return tok.text if len(tok.text) <= 20 else tok.text[:20] + "…"


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


class Cursor:
    """The tokens of one line (NEWLINE/EOF last, comments removed) and the position in them."""

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
        if tok.kind not in END_KINDS:
            self.i += 1
        return tok

    def at_end(self) -> bool:
        return self.toks[self.i].kind in END_KINDS

    def at_word(self, word: str) -> bool:
        tok = self.toks[self.i]
        return tok.kind in WORD_KINDS and tok.text.upper() == word

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
        return new_tuple(A.Span, (start.line, start.column, last.line, last.end_column))

    @staticmethod
    def tok_span(tok: Token) -> A.Span:
        if tok.kind is K.NEWLINE or tok.kind is K.EOF:
            return A.Span(tok.line, tok.column, tok.line, tok.column)
        # Fields 2..5 of a token are exactly (line, column, end_line, end_column).
        return new_tuple(A.Span, tok[2:6])

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
        if tok.kind in END_KINDS and self.i > 0:
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
    ) -> Fail:
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
        return Fail(self.issue(tok, message, rule, suggestion, code, replacement))

    def word_after(self, tok: Token) -> str:
        """The word glued to the right of `tok` (no space between), or ""."""
        for k in range(len(self.toks) - 1):
            if self.toks[k] is tok:
                nxt = self.toks[k + 1]
                return nxt.text if nxt.kind in WORD_KINDS and not nxt.prefix else ""
        return ""

    def missing(self, what: str, context: str) -> Fail:
        """`what` was expected at the current token (generic "Expected …" message)."""
        tok = self.peek()
        verb = "Add" if tok.kind in END_KINDS else "Write"
        return self.fail(
            tok, f"Expected {what} {context}, found {describe(tok)}", "syntax-error",
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

    def v_construct(self, tok: Token, construct: Construct) -> Fail:
        """The one finding for a MELFA BASIC V construct: what it is, the IV way or none."""
        return self.fail(
            tok,
            f"{construct.what} is MELFA BASIC V; the CR2B-574 runs MELFA BASIC IV, "
            "which does not have it",
            "melfa-basic-v",
            construct.in_iv
            or "Not available in IV: MELFA BASIC IV has no equivalent, so remove the line.",
        )
