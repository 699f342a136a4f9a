"""MELFA BASIC IV toolkit: lexer, parser, checker, line numbering, points files.

Pure logic: no files, no robot, no clock. Positions are 1-based lines and columns, ranges
end-exclusive (see `melfa.lang.diagnostics`); tokens, tree spans and diagnostics all use it.

>>> from melfa.lang import check
>>> [d.message for d in check("WIHLE M1 < 3\\nWEND\\n")][:1]
['WIHLE is not a MELFA BASIC IV word: did you mean WHILE?']

What it does not do: talk to a robot, read files, or run programs (`melfa.sim.interp` runs
the tree this package builds).
"""

from melfa.lang.blocks import BlockStructure, match_blocks
from melfa.lang.check import check, check_ast
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.lexer import tokenize, untokenize
from melfa.lang.parser import parse, parse_tokens
from melfa.lang.tokens import Token, TokenKind
from melfa.lang.typos import suggest

__all__ = [
    "BlockStructure",
    "Diagnostic",
    "Severity",
    "Token",
    "TokenKind",
    "check",
    "check_ast",
    "match_blocks",
    "parse",
    "parse_tokens",
    "suggest",
    "tokenize",
    "untokenize",
]
