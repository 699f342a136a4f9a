"""Program text the controller accepts: ASCII only, code untouched.

The controller takes ASCII only (the protocol layer refuses anything else, and rightly: a
byte it cannot decode is a 6010). Real programs, the thesis's included, carry Catalan or
Spanish accents in comments and strings, and the thesis uploaded them, so before an upload
those two token kinds are transliterated: Unicode NFKD, combining marks dropped, ``?`` for
whatever is still not ASCII (``"`` too inside a string, so it stays one string). Code (names,
keywords) is never changed: non-ASCII there is the checker's L4310, a real error.

>>> to_controller_ascii("' Piràmide\\nPRINT \\"peça\\"\\nMOV P1 ' repòs\\n")
('\\' Piramide\\nPRINT "peca"\\nMOV P1 \\' repos\\n', (1, 2, 3))
>>> to_controller_ascii("MOV P1\\n")
('MOV P1\\n', ())
"""

from __future__ import annotations

import unicodedata
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Final

from melfa.lang.lexer import tokenize
from melfa.lang.tokens import Token, TokenKind

REPLACEMENT: Final = "?"
"""Stands in for a character with no ASCII form (``ß``, ``€``, CJK…)."""


def ascii_fold(text: str, *, forbid: str = "") -> str:
    """NFKD, combining marks dropped, `REPLACEMENT` for the rest and for ``forbid``.

    >>> ascii_fold("Mà cap avall, 5 €")
    'Ma cap avall, 5 ?'
    """
    if text.isascii() and not any(c in text for c in forbid):
        return text
    out = []
    for char in unicodedata.normalize("NFKD", text):
        if unicodedata.combining(char):
            continue
        ok = char.isascii() and char not in forbid and (char.isprintable() or char == "\t")
        out.append(char if ok else REPLACEMENT)
    return "".join(out)


@dataclass(frozen=True)
class AsciiConversion:
    """What `convert` did: the text to send and the 1-based lines it changed, by kind."""

    text: str
    comment_lines: tuple[int, ...] = ()
    string_lines: tuple[int, ...] = ()

    @property
    def changed_lines(self) -> tuple[int, ...]:
        """Every changed line, ascending."""
        return tuple(sorted({*self.comment_lines, *self.string_lines}))

    def note(self) -> str | None:
        """One sentence for the user, or None if nothing changed.

        >>> convert("' à\\n' é\\nPRINT \\"ç\\"\\n").note()
        'comments and strings on lines 1, 2, 3 sent without accents; your file is unchanged'
        """
        if not self.changed_lines:
            return None
        what = (
            "comments and strings"
            if self.comment_lines and self.string_lines
            else "comments"
            if self.comment_lines
            else "strings"
        )
        return (
            f"{what} on {_lines(self.changed_lines)} sent without accents; your file is unchanged"
        )


def convert(program: str) -> AsciiConversion:
    """Transliterate comments and strings of ``program`` to ASCII; see the module doc."""
    if program.isascii():
        return AsciiConversion(program)
    _, conversion = fold_tokens(tokenize(program))
    return conversion


def fold_tokens(tokens: list[Token]) -> tuple[list[Token], AsciiConversion]:
    """`convert` on tokens already made (an upload plan tokenizes once): the tokens with
    comments and strings folded, and what changed. Code tokens are the same objects."""
    out: list[Token] = []
    parts: list[str] = []
    comments: set[int] = set()
    strings: set[int] = set()
    for token in tokens:
        text = token.text
        if not text.isascii():
            if token.kind is TokenKind.COMMENT:
                text = ascii_fold(text)
                comments.add(token.line)
            elif token.kind is TokenKind.STRING:
                text = '"' + ascii_fold(text[1:-1], forbid='"') + '"'
                strings.add(token.line)
        out.append(token if text is token.text else token._replace(text=text))
        parts.append(token.prefix + text)
    conversion = AsciiConversion("".join(parts), tuple(sorted(comments)), tuple(sorted(strings)))
    return out, conversion


def to_controller_ascii(program: str) -> tuple[str, tuple[int, ...]]:
    """``(text to send, changed 1-based lines)``; see `convert` for the kinds."""
    result = convert(program)
    return result.text, result.changed_lines


@dataclass(frozen=True)
class NonAscii:
    """Where a character the controller cannot take is (1-based line and column)."""

    line: int
    column: int
    char: str


def find_non_ascii(lines: str | Sequence[str]) -> NonAscii | None:
    """The first non-ASCII character, or None.

    >>> find_non_ascii("MOV P1\\nMOV Pé\\n")
    NonAscii(line=2, column=6, char='é')
    """
    rows = lines.splitlines() if isinstance(lines, str) else lines
    for number, row in enumerate(rows, start=1):
        for column, char in enumerate(row, start=1):
            if not char.isascii():
                return NonAscii(number, column, char)
    return None


def _lines(numbers: Sequence[int]) -> str:
    """``line 4`` / ``lines 1, 3, 6``."""
    if len(numbers) == 1:
        return f"line {numbers[0]}"
    return "lines " + ", ".join(str(n) for n in numbers)
