"""`Reporter`: how the checker's mixins report a finding, written once.

The checker's analyser (`melfa.lang.check`) is made of mixins, one per family of checks
(`check_names`, `check_routines`, `check_v`); each subclasses this base and reports through
its one `add`, which appends to the analyser's ``out``.
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Diagnostic, Severity


class Reporter:
    """The one `add` of the checker's mixins; the analyser supplies ``out``."""

    out: list[Diagnostic]

    def add(
        self,
        span: A.Span,
        severity: Severity,
        message: str,
        rule: str,
        code: str | None = None,
        suggestion: str | None = None,
        replace: str | None = None,
    ) -> None:
        """Report a finding on `span` (``replace``: the text that fixes it there)."""
        self.out.append(
            Diagnostic(
                span.line, span.column, span.end_line, span.end_column, severity, message,
                rule, code, suggestion, replace,
            )
        )  # fmt: skip


__all__ = ["Reporter"]
