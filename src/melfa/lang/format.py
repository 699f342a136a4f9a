"""`melfa fmt`: one spelling for the language's own words, nothing else changed.

The controller upper-cases everything outside strings and comments when it reads a
program [S2 §4.3.7(1)], so the case of a word never changes what it means. We upper-case
the language's words (statement keywords, operator words such as ``AND``, built-in
function names, element names ``.X``/``.FL1`` and the ``&H``/``&B`` prefixes) and keep
the user's own names (variables, labels) as written: ``mov pGoal, -80`` becomes
``MOV pGoal, -80``. Strings and comments are never touched, except the word ``REM`` that
opens a comment. Works on tokens, so a program with syntax errors is formatted line by
line without damage (an ERROR token is copied as it is).
"""

from __future__ import annotations

import enum

from melfa.lang.diagnostics import Diagnostic
from melfa.lang.lexer import tokenize
from melfa.lang.numbering import renumber, strip
from melfa.lang.record import Record
from melfa.lang.tokens import Token, TokenKind

__all__ = ["FormatResult", "LineNumbers", "format_program", "normalize_case"]


class LineNumbers(enum.Enum):
    """What `format_program` does with step numbers."""

    KEEP = "keep"
    NUMBER = "number"  # number every line (`melfa.lang.numbering.renumber`)
    STRIP = "strip"  # remove numbers no jump uses (`melfa.lang.numbering.strip`)


class FormatResult(Record):
    """The formatted text, or the original when `diagnostics` hold an error."""

    text: str
    diagnostics: tuple[Diagnostic, ...] = ()

    @property
    def ok(self) -> bool:
        return not any(d.is_error for d in self.diagnostics)


def _normal(tok: Token) -> str:
    kind = tok.kind
    if kind is TokenKind.KEYWORD or kind is TokenKind.DOT_ELEMENT:
        return tok.text.upper()
    if kind is TokenKind.HEX or kind is TokenKind.BIN:
        return tok.text.upper()
    if kind is TokenKind.COMMENT and tok.text[:3].upper() == "REM":
        return "REM" + tok.text[3:]
    return tok.text


def normalize_case(text: str) -> str:
    """Upper-case the language's words; leave names, strings and comments alone.

    >>> normalize_case('10 mov pGoal, -80 \\' mov here\\n20 if m_in(1)=1 then *Loop')
    "10 MOV pGoal, -80 ' mov here\\n20 IF m_in(1)=1 THEN *Loop"
    >>> normalize_case('c$ = "mov"\\np1.x = &h0f')
    'c$ = "mov"\\np1.X = &H0F'
    """
    return "".join(tok.prefix + _normal(tok) for tok in tokenize(text))


def format_program(
    text: str,
    line_numbers: LineNumbers = LineNumbers.KEEP,
    *,
    start: int = 10,
    step: int = 10,
) -> FormatResult:
    """Normalise keyword case, then number or strip lines as asked.

    When numbering cannot be done without changing the program (a jump to a step that
    does not exist, steps out of order), the text comes back unchanged with the reasons.

    >>> format_program("servo on\\nend", LineNumbers.NUMBER).text
    '10 SERVO ON\\n20 END'
    """
    cased = normalize_case(text)
    if line_numbers is LineNumbers.KEEP:
        return FormatResult(cased)
    result = renumber(cased, start, step) if line_numbers is LineNumbers.NUMBER else strip(cased)
    if not result.ok:
        return FormatResult(text, result.diagnostics)
    return FormatResult(result.text, result.diagnostics)
