"""MELFA BASIC IV toolkit: lexer, parser, checker, line numbering, points files.

Pure logic: no files, no robot, no clock. Positions are 1-based lines and columns
(see `melfa.lang.diagnostics`).
"""

from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.lexer import tokenize, untokenize
from melfa.lang.tokens import Token, TokenKind

__all__ = ["Diagnostic", "Severity", "Token", "TokenKind", "tokenize", "untokenize"]
