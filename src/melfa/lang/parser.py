"""Error-recovering recursive-descent parser: text to `melfa.lang.ast.Program`.

`parse` never raises. Each text line is parsed on its own (MELFA BASIC IV has one statement
per step), so a broken line can never hide the lines after it. Inside a line the parser
resumes at the structural keywords THEN and ELSE: ``IF end < start THEN HOPEN`` reports the
bad condition *and* the HOPEN without a hand number. Otherwise the rest of the line becomes an
`InvalidStatement` and only the first mistake on it is reported (no cascades).

This module is the line driver and the entry points (`parse`, `parse_tokens`, `parse_lines`,
`parse_line`, `parse_constant`): it splits the tokens into lines, reads each line's number,
label and comment, and dispatches its statement by the first word to the families, one
module each: `parse_expr` (values, by precedence climbing), `parse_motion`, `parse_flow`,
`parse_defs`, `parse_io`, all reading tokens through `parse_cursor`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from operator import itemgetter

from melfa.lang import ast as A  # noqa: N812  (short alias: the parser builds many nodes)
from melfa.lang.grammar import COMMANDS
from melfa.lang.lexer import tokenize
from melfa.lang.model import foreign_constructs
from melfa.lang.parse_cursor import (
    END_KINDS,
    Fail,
    K,
    Labels,
    describe,
    new_tuple,
    rename_hint,
    to_int,
)
from melfa.lang.parse_defs import DefStatements
from melfa.lang.parse_flow import FlowStatements
from melfa.lang.parse_io import IOStatements
from melfa.lang.parse_motion import MotionStatements
from melfa.lang.tokens import FUNCTIONS, STATEMENT_KEYWORDS, Token
from melfa.lang.typos import suggest


def step_number(digits: str) -> int:
    """The value of a step number's digits, as `parse` reads it (`melfa.lang.reparse`)."""
    return to_int(digits)


class _LineParser(MotionStatements, FlowStatements, DefStatements, IOStatements):
    """Parses the tokens of one line (NEWLINE/EOF last, comments removed): a statement of
    any family, with recovery to the end of the line or a stop word."""

    # ---------------------------------------------------------------------- statements

    def statement(self, stop: frozenset[str] = frozenset()) -> A.Statement:
        """Parse one statement; on error, skip to a `stop` word or the end of the line."""
        start_i = self.i
        start = self.toks[self.i]
        self.depth = 0
        try:
            return self.statement_inner()
        except Fail as failure:
            toks = self.toks
            i = max(self.i, start_i)
            while toks[i].kind not in END_KINDS and not (
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
                    rename_hint(word),
                )
            method = _DISPATCH.get(word)
            if method is not None:
                self.i += 1
                return method(self, tok)
            command = COMMANDS.get(word)
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
        raise self.fail(tok, f"Expected a statement, found {describe(tok)}", "invalid-statement")

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
            if nxt.kind in END_KINDS and word in self.labels:
                raise self.fail(
                    tok,
                    f"Label needs to start with * ({tok.text})",
                    "label-without-star",
                    f"Write *{tok.text} to define the label.",
                    replacement=f"*{tok.text}",
                )
            raise self.fail(
                nxt if nxt.kind not in END_KINDS else tok,
                f"Invalid statement: expected '=' after {tok.text} (assignment), "
                f"found {describe(nxt)}",
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


_DISPATCH: dict[str, Callable[[_LineParser, Token], A.Statement]] = {
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

assert set(_DISPATCH) | set(COMMANDS) | {"REM"} == STATEMENT_KEYWORDS


def parse_line(tokens: list[Token], labels: Labels, start: int = 0, end: int = -1) -> A.Line:
    """The tree of the line whose tokens are ``tokens[start:end + 1]`` (``end``: its NEWLINE
    or the EOF; -1: the first from ``start``); `labels` are the file's, asked only by a line
    with a mistake. A line lexed on its own is ``parse_line(tokenize(line, number), …)``."""
    if end < 0:
        end = next(k for k in range(start, len(tokens)) if tokens[k].kind in END_KINDS)
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
    span = new_tuple(A.Span, (lineno, 1, lineno, end_tok.column))
    number = label = label_text = comment = None
    number_span = label_span = None
    k = i
    if k < j and tokens[k].kind is K.LINE_NUMBER:
        tok = tokens[k]
        number = to_int(tok.text)
        number_span = new_tuple(A.Span, (lineno, tok.column, lineno, tok.end_column))
        k += 1
    if k < j and tokens[k].kind is K.LABEL:
        tok = tokens[k]
        label_text = tok.text[1:]
        label = label_text.upper()
        label_span = new_tuple(A.Span, (lineno, tok.column, lineno, tok.end_column))
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
            f"Unexpected {describe(extra)} after the end of the statement (one statement per line)",
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
            raise parser.fail(start, f"Expected '(', found {describe(start)}")
        node = parser.paren()
    except Fail as failure:
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
