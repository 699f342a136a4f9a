"""Which program text the controller refuses to store, and with which number.

The controller checks a step when it is entered (EMDAT/EDATA errors carry a character
position [DOC S1 §5.2.7–5.2.8]) and SAVE refuses a program with a syntax error (L4220).
We ask `melfa.lang`'s parser (the same one behind `melfa.lang.check`, which students see)
and refuse for its *syntax* findings only, each with its controller code (L4220, L4210 …).
The checker's other findings (undefined variables, missing jump targets, style) are left to
RUN, as on the controller, which stores such programs and fails when it reaches them.
"""

from __future__ import annotations

from melfa.lang.ast import ParseIssue
from melfa.lang.model import MAX_LINE_LENGTH, MAX_LINE_NUMBER
from melfa.lang.parser import parse
from melfa.protocol.error_table import LINE_NUMBER_RANGE, STATEMENT_TOO_LONG, SYNTAX

DEFAULT_NUMBER = SYNTAX
"""L4220 "Syntax error": a finding without a controller code of its own."""


def first_syntax_error(text: str) -> tuple[int, int] | None:
    """(error number, 1-based column) of the first syntax problem, or None.

    >>> first_syntax_error("10 MOV P1\\n")
    >>> first_syntax_error("10 MOV (\\n")
    (4220, 8)
    """
    for line in parse(text).lines:
        # What the interpreter refuses at load too (`melfa.sim.interp.compiler`): a step
        # number outside 1…32767, a step over 127 characters.
        if line.number is not None and not 1 <= line.number <= MAX_LINE_NUMBER:
            return LINE_NUMBER_RANGE, 1
        if line.span.end_column - 1 > MAX_LINE_LENGTH:
            return STATEMENT_TOO_LONG, MAX_LINE_LENGTH + 1
        for issue in line.issues + _statement_issues(line.statement):
            code = issue.code or ""
            number = int(code[1:]) if code[1:].isdigit() else DEFAULT_NUMBER
            return number, issue.span.column
    return None


def _statement_issues(statement: object) -> tuple[ParseIssue, ...]:
    issue = getattr(statement, "issue", None)
    return (issue,) if isinstance(issue, ParseIssue) else ()
