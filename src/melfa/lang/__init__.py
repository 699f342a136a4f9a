"""MELFA BASIC IV toolkit: lexer, parser, checker, line numbering, points files.

Pure logic: no files, no robot, no clock. Positions are 1-based lines and columns
(see `melfa.lang.diagnostics`).
"""

from melfa.lang.diagnostics import Diagnostic, Severity

__all__ = ["Diagnostic", "Severity"]
