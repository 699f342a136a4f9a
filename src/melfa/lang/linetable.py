"""`LineTable`: a program's lines read once, for the checker's passes.

The checker runs on every keystroke, and most of its passes need a few lines only (the
GOSUBs, the labels, the DEFs, the lines too long). Walking every line in Python once per
pass, each reading the line's fields again, cost about a third of the checker's analysis of
1,000 lines (bench/bench_check.py). Here each field a pass needs is read once for all the
lines, and the lines of each statement class are listed, so that a pass's Python code runs
for its own lines only.

>>> from melfa.lang.parser import parse
>>> table = LineTable(parse("10 *A\\n20 GOSUB *A\\nMOV P1\\n"))
>>> table.having({A.Gosub, A.Move}), table.numbered, table.labelled
([1, 2], [0, 1], [0])
>>> table.line_index == {"A": 0, 10: 0, 20: 1}
True
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from functools import cached_property
from itertools import chain, compress, repeat
from operator import is_not

from melfa.lang import ast as A  # noqa: N812


class LineTable:
    """One program's lines by field; index ``i`` is ``program.lines[i]``."""

    def __init__(self, program: A.Program) -> None:
        lines = program.lines
        self.lines = lines
        self.statements: list[A.Statement | None] = [line.statement for line in lines]
        self.classes: list[type] = list(map(type, self.statements))
        by_class: defaultdict[type, list[int]] = defaultdict(list)
        for index, cls in enumerate(self.classes):
            by_class[cls].append(index)
        self._by_class = by_class
        self.numbers: list[int | None] = [line.number for line in lines]
        self.labels: list[str | None] = [line.label for line in lines]
        indexes = range(len(lines))
        self.numbered: list[int] = list(compress(indexes, map(is_not, self.numbers, repeat(None))))
        self.labelled: list[int] = list(compress(indexes, map(is_not, self.labels, repeat(None))))

    def having(self, classes: Iterable[type]) -> list[int]:
        """The indexes of the lines whose statement is of one of `classes`, in order (a list
        the caller reads, never changes)."""
        found = [self._by_class[cls] for cls in classes if cls in self._by_class]
        if len(found) == 1:
            return found[0]
        return sorted(chain.from_iterable(found))

    def has(self, cls: type) -> bool:
        """Whether a line's statement is a `cls`."""
        return cls in self._by_class

    @cached_property
    def line_index(self) -> dict[str | int, int]:
        """Label or step number -> the index of its line (the first, if repeated)."""
        where: dict[str | int, int] = {}
        labels, numbers = self.labels, self.numbers
        for index in reversed(self.labelled):  # from the end: the first line is kept
            where[labels[index]] = index  # type: ignore[index]  # labelled: not None
        for index in reversed(self.numbered):
            where[numbers[index]] = index  # type: ignore[index]
        return where

    def longest(self) -> int:
        """The end column of the longest line (1 for an empty program)."""
        return max([line.span[3] for line in self.lines], default=1)


__all__ = ["LineTable"]
