"""Read each distinct line once: the check of a whole program, and again on every keystroke.

The editor sends the whole program after each edit and `check` reads all of it, but a
keystroke changes one line, and a program repeats lines (``HOPEN 1``, ``RETURN``, ``DLY
0.5``, ``MVS PTMP``). MELFA BASIC IV has one statement a line, and both the lexer and the
parser read each line on its own (a line's tokens and tree depend on its text and its line
number, nothing else), so `LineCache.parse` keeps each line's tree and

* gives it back when the same text comes again on the same line (the editor's next check);
* moves it (`melfa.lang.relocate`) when the same text comes on another line: a repeated
  line, a line shifted by one inserted above it, or ``20 HOPEN 1`` after ``10 HOPEN 1``
  (a step number is read as its digits' width, its value put in the copy);
* lexes and parses the other lines, only those, in one lexer pass over them.

The checker's whole-program analysis still runs on every call.

The one exception: a line with a bare word that might be a label without its ``*`` asks the
file's labels for its message (`melfa.lang.parser.Labels`); such a line is parsed again
every time. Lines with parse issues are read again wherever they recur (`relocate`). A
cache holds at most `LineCache.limit` lines (the oldest half goes first).

>>> cache = LineCache()
>>> text = "10 MOV P1\\n20 HOPEN 1\\n"
>>> cache.parse(text) == parse(text), len(cache)
(True, 3)
>>> cache.parse(text.replace("HOPEN 1", "HOPEN 2")) == parse("10 MOV P1\\n20 HOPEN 2\\n")
True
"""

from __future__ import annotations

import re
from collections.abc import Callable

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.lexer import tokenize
from melfa.lang.parser import Labels, parse, parse_line, parse_lines, step_number
from melfa.lang.relocate import moved

# A line and the line end the lexer reads as one NEWLINE (CR LF, CR or LF).
_LINES = re.compile(r"[^\r\n]*(?:\r\n|\r|\n)")
# What str.splitlines ends a line at besides CR and LF, which the lexer does not.
_OTHER_ENDS = "\v\f\x1c\x1d\x1e\x85\u2028\u2029"
# A step number the lexer reads as one: digits, then a blank or the line's end (not `10E3`,
# `10.5` or `10#`, numbers whose value the digits alone do not give).
_STEP = re.compile(r"[ \t]*(\d+)(?=[ \t\r\n]|\Z)", re.ASCII)
_STEP_START = " \t0123456789"
_ZEROS = str.maketrans("123456789", "000000000")

FAST_FROM = 40
"""Lines not seen on their line number from which `melfa.lang.fastline` reads those of its
shapes: compiling its patterns costs about what lexing and parsing 40 lines does, so `melfa
check` of a small file (start-up, bench/bench_check.py) and the editor's check after a
keystroke do not pay it."""

LINE_LIMIT = 50_000
"""Lines kept by the default cache: a class of 40 with programs of ~1,000 lines."""


def _key(piece: str) -> tuple[str, int | None]:
    """The text a line's tree is kept by (its step number's digits as zeros: the tree of
    ``10 HOPEN 1`` is that of ``20 HOPEN 1`` with another value), and that value (None
    when the key is the text itself)."""
    step = _STEP.match(piece)
    if step is None:
        return piece, None
    digits = step.group(1)
    at = step.start(1)
    return piece[:at] + digits.translate(_ZEROS) + piece[step.end(1) :], step_number(digits)


def _pieces(text: str) -> list[str]:
    """The lines of `text`, each with its line end, and the last without one ("" when the
    text ends with a line end): the lines the lexer reads."""
    if not any(map(text.__contains__, _OTHER_ENDS)):  # str.splitlines is several times faster
        pieces = text.splitlines(True)
        if not pieces or pieces[-1][-1:] in "\r\n":
            pieces.append("")
        return pieces
    pieces = _LINES.findall(text)
    pieces.append(text[sum(map(len, pieces)) :])
    return pieces


def _fast_reader() -> Callable[[str, int], A.Line | None]:
    """`melfa.lang.fastline.read_line`, imported on the first use: its patterns compile on
    import, which a small file's check (start-up) and a keystroke's do not pay."""
    from melfa.lang.fastline import read_line

    return read_line


class LineCache:
    """Trees of lines by line number and text, and one tree of each text, for `parse`."""

    def __init__(self, limit: int = LINE_LIMIT) -> None:
        self.limit = limit
        self._lines: dict[tuple[int, str], A.Line] = {}  # (line number, text) -> tree
        self._texts: dict[str, A.Line] = {}  # `_key` text -> a tree of it, on some line

    def __len__(self) -> int:
        return len(self._lines)

    def parse(self, text: str) -> A.Program:
        """The tree of `text`, equal to `melfa.lang.parser.parse(text)`."""
        return self.read(text)[0]

    def read(self, text: str) -> tuple[A.Program, list[int]]:
        """The tree of `text`, and for each line the index of the first line written exactly
        like it (its own when it is the first): the checker says nothing twice about one
        text (`melfa.lang.check.check_ast`)."""
        pieces = _pieces(text)
        first: dict[str, int] = {}
        repeats = list(map(first.setdefault, pieces, range(len(pieces))))
        keys = list(enumerate(pieces, 1))
        lines = list(map(self._lines.get, keys))
        if None in lines:
            self._read(text, keys, lines)
        if len(self._lines) > self.limit:
            self._lines = dict(list(self._lines.items())[len(self._lines) // 2 :])
        if len(self._texts) > self.limit:
            self._texts = dict(list(self._texts.items())[len(self._texts) // 2 :])
        return A.Program(tuple(lines)), repeats  # type: ignore[arg-type]  # no None left

    def _read(self, text: str, keys: list[tuple[int, str]], lines: list[A.Line | None]) -> None:
        """Fill the Nones of `lines`: move the trees of texts seen, read the others (when
        they are many, those of the commonest shapes by `melfa.lang.fastline` as they come,
        the rest by the lexer and the parser in one pass)."""
        kept, texts = self._lines, self._texts
        labels = Labels(lambda: tokenize(text))  # the file's, only if a line asks
        fast = _fast_reader() if lines.count(None) >= FAST_FROM else None
        fresh: dict[str, int] = {}  # key text -> index of its first line for the parser
        again: list[tuple[int, str, int | None]] = []  # lines whose text is in `fresh`
        for n, line in enumerate(lines):
            if line is not None:
                continue
            lineno, piece = key_line = keys[n]
            key, number = _key(piece) if piece[:1] in _STEP_START else (piece, None)
            model = texts.get(key)
            if model is not None:
                lines[n] = kept[key_line] = moved(model, lineno, number, model.number)
            elif key in fresh:
                again.append((n, key, number))
            else:
                line = fast(piece, lineno) if fast is not None else None
                if line is None:
                    fresh[key] = n
                else:
                    lines[n] = kept[key_line] = texts[key] = line
        if fresh:
            self._parse_fresh(list(fresh.items()), keys, lines, labels)
        for n, key, number in again:
            model = texts.get(key)
            lineno, piece = keys[n]
            if model is not None:
                lines[n] = kept[keys[n]] = moved(model, lineno, number, model.number)
            else:  # asks the file's labels, or has a parse issue: read again
                labels.asked = False
                lines[n] = line = parse_line(tokenize(piece, lineno), labels)
                if not labels.asked:
                    kept[keys[n]] = line

    def _parse_fresh(
        self,
        fresh: list[tuple[str, int]],
        keys: list[tuple[int, str]],
        lines: list[A.Line | None],
        labels: Labels,
    ) -> None:
        """Lex the lines `fresh` names in one pass (the lexer is cheapest over many lines at
        once), each with its own line number, and parse them."""
        kept, texts = self._lines, self._texts
        indices = [n for _, n in fresh]
        numbers = [keys[n][0] for n in indices]
        numbers.append(numbers[-1] + 1)  # after the last line end: an empty line, not read
        tokens = tokenize("".join(keys[n][1] for n in indices), numbers[0], numbers[1:])
        # One more line when the text read ends with a line end: zip leaves it out.
        for (key, n), (line, asked) in zip(fresh, parse_lines(tokens, labels), strict=False):
            lines[n] = line
            if not asked:
                kept[keys[n]] = line
                if not line.issues:
                    texts[key] = line

    def clear(self) -> None:
        self._lines = {}
        self._texts = {}


EDITOR = LineCache()
"""The cache of `melfa.lang.check.check` and `melfa.lang.project.check_project`."""

__all__ = ["EDITOR", "LINE_LIMIT", "LineCache", "parse"]
