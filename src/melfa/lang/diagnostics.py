"""Diagnostics: what the checker says about a program, and where.

Positions follow one convention in the whole of `melfa.lang`: lines and columns are
1-based, as an editor shows them; a range ends *after* its last character
(`end_column` is exclusive). The browser edge converts to its own convention.
"""

from __future__ import annotations

import enum

from melfa.lang.record import Record


class Severity(enum.Enum):
    """How bad a diagnostic is. Only errors stop an upload."""

    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


class Diagnostic(Record):
    """One finding of the checker.

    `code` is the controller's own error number when one exists (``"L4220"``), so a
    student can look it up in the Mitsubishi manual; `rule` is our stable name for the
    check (documented in docs/diagnostics.md). `suggestion` is a fix hint, when we have one;
    `replace` the text that fixes it when written over the diagnostic's span (``PHOME`` for a
    misspelt ``PHOM``), for an editor's one-click fix.
    """

    line: int
    column: int
    end_line: int
    end_column: int
    severity: Severity
    message: str
    rule: str
    code: str | None = None
    suggestion: str | None = None
    replace: str | None = None

    def __post_init__(self) -> None:
        if self.line < 1 or self.column < 1:
            raise ValueError(f"positions are 1-based, got {self.line}:{self.column}")
        if (self.end_line, self.end_column) < (self.line, self.column):
            raise ValueError("a diagnostic cannot end before it starts")

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    def to_json(self) -> dict[str, object]:
        """The JSON shape shared by `melfa check --format json` and the web API."""
        return {
            "line": self.line,
            "column": self.column,
            "end_line": self.end_line,
            "end_column": self.end_column,
            "severity": self.severity.value,
            "code": self.code,
            "rule": self.rule,
            "message": self.message,
            "suggestion": self.suggestion,
            "replace": self.replace,
        }
