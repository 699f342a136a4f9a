"""`Reporter`: how the checker's mixins report a finding, declared once.

The checker's analyser (`melfa.lang.check`) is made of mixins, one per family of checks
(`check_names`, `check_routines`, `check_v`); each reports through the analyser's one `add`
(`check_names.NameChecks.add`). The mixins that only use it subclass this protocol, so the
type checker knows the method without a stub of their own.
"""

from __future__ import annotations

from typing import Protocol

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Severity


class Reporter(Protocol):
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
        ...


__all__ = ["Reporter"]
