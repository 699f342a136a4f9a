"""Reparse only the lines that changed: the editor's check on every keystroke.

The editor sends the whole program after each edit and `check` reads all of it, but a
keystroke changes one line. MELFA BASIC IV has one statement a line, and both the lexer and
the parser read each line on its own (a line's tokens and tree depend on its text and its
number, nothing else), so a line's tree can be kept and given back when the same text comes
again on the same line. `LineCache.parse` lexes and parses only the lines it has not seen;
the checker's whole-program analysis still runs on every call.

The one exception: a line with a bare word that might be a label without its ``*`` asks the
file's labels for its message (`melfa.lang.parser.Labels`); such a line is parsed again
every time. A cache holds at most `LineCache.limit` lines (the oldest half goes first).

>>> cache = LineCache()
>>> text = "10 MOV P1\\n20 HOPEN 1\\n"
>>> cache.parse(text) == parse(text), len(cache)
(True, 3)
>>> cache.parse(text.replace("HOPEN 1", "HOPEN 2")) == parse("10 MOV P1\\n20 HOPEN 2\\n")
True
"""

from __future__ import annotations

import re
from operator import itemgetter

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.lexer import tokenize
from melfa.lang.parser import Labels, parse, parse_line
from melfa.lang.tokens import TokenKind

# A line and the line end the lexer reads as one NEWLINE (CR LF, CR or LF).
_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)")

MOSTLY_NEW = 4
"""More than one line in this many not seen before: lex the whole text in one pass."""
LINE_LIMIT = 50_000
"""Lines kept by the default cache: a class of 40 with programs of ~1,000 lines."""


class LineCache:
    """Trees of lines by (line number, text), for `parse`."""

    def __init__(self, limit: int = LINE_LIMIT) -> None:
        self.limit = limit
        self._lines: dict[tuple[int, str], A.Line] = {}

    def __len__(self) -> int:
        return len(self._lines)

    def parse(self, text: str) -> A.Program:
        """The tree of `text`, equal to `melfa.lang.parser.parse(text)`."""
        pieces = _LINES.findall(text)
        pieces.append(text[sum(map(len, pieces)) :])  # the last line, without a line end
        keys = list(enumerate(pieces, 1))
        kept = self._lines
        lines = list(map(kept.get, keys))
        missing = lines.count(None)
        if missing > len(lines) // MOSTLY_NEW:
            # Mostly new (a file just opened): one lexer pass over the whole text is
            # cheaper than one a line, and its tokens carry the right line numbers.
            tokens = tokenize(text)
            labels = Labels(tokens)
            kinds = list(map(itemgetter(0), tokens))
            start, last = 0, len(tokens) - 1
            for n, line in enumerate(lines):
                try:
                    end = kinds.index(TokenKind.NEWLINE, start)
                except ValueError:
                    end = last
                if line is None:
                    labels.asked = False
                    lines[n] = line = parse_line(tokens, labels, start, end)
                    if not labels.asked:
                        kept[keys[n]] = line
                start = end + 1
        elif missing:
            labels = Labels(lambda: tokenize(text))
            for n, line in enumerate(lines):
                if line is None:
                    number, piece = keys[n]
                    labels.asked = False
                    lines[n] = line = parse_line(tokenize(piece, number), labels)
                    if not labels.asked:
                        kept[keys[n]] = line
        if len(kept) > self.limit:
            self._lines = dict(list(kept.items())[len(kept) // 2 :])
        return A.Program(tuple(lines))  # type: ignore[arg-type]  # every None was parsed

    def clear(self) -> None:
        self._lines = {}


EDITOR = LineCache()
"""The cache of `melfa.lang.check.check` and `melfa.lang.project.check_project`."""

__all__ = ["EDITOR", "LINE_LIMIT", "LineCache", "parse"]
