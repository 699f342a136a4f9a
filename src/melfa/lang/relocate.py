"""A line's tree moved to another text line: the same text read once, kept for every line.

A line's tree depends only on its text (MELFA BASIC IV has one statement a line; the lexer
and the parser read each line on its own), and every span in it is on that line. So when a
text comes again on another line (``HOPEN 1``, ``RETURN``, ``MVS PTMP`` recur all over a
real program), its tree is the first one's with every span's line changed, and, for a step
number of the same width (``10 HOPEN 1``, ``20 HOPEN 1``), the number's value changed.
Copying a tree this way costs a fraction of lexing and parsing the line again
(bench/bench_check.py), which is what `melfa.lang.reparse.LineCache` does with it.

Lines with parse issues are not moved (an issue is shared by the line and the node where
parsing broke off, and its message may quote the text): they are read again.

>>> from melfa.lang.parser import parse
>>> first, again = parse("10 MOV P1, -50\\n20 MOV P1, -50").lines
>>> moved(first, 2, 20) == again
True
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from melfa.lang import ast as A  # noqa: N812

_Mover = Callable[[Any, int], Any]

_new_object = object.__new__
_new_tuple = tuple.__new__


def _move_items(items: tuple[Any, ...], line: int) -> tuple[Any, ...]:
    """A tuple of nodes (None for an element left out: ``(1,,3)``)."""
    movers = _MOVERS
    return tuple([None if item is None else movers[item.__class__](item, line) for item in items])


def _compile(cls: type) -> _Mover:
    """``move(node, line)`` for one node class: a copy of `node` whose span and whose
    children's spans are on `line`. Generated (as `melfa.lang.record` compiles ``__init__``)
    so that each node costs one call, not a loop over its fields."""
    body = [
        "def move(node, line):",
        "    s = node.__dict__",
        "    new = NEW(CLS)",
        "    d = new.__dict__",
        "    d.update(s)",
        "    span = s['span']",
        "    d['span'] = TUPLE(SPAN, (line, span[1], line, span[3]))",
    ]
    for name in A.CHILD_FIELDS[cls]:
        body.append(f"    v = s[{name!r}]")
        body.append(f"    if v is not None: d[{name!r}] = MOVERS[v.__class__](v, line)")
    body.append("    return new")
    namespace: dict[str, Any] = {
        "NEW": _new_object,
        "CLS": cls,
        "TUPLE": _new_tuple,
        "SPAN": A.Span,
        "MOVERS": _MOVERS,
    }
    exec("\n".join(body), namespace)
    mover: _Mover = namespace["move"]
    mover.__qualname__ = f"move_{cls.__name__}"
    return mover


class _Movers(dict[type, _Mover]):
    """Node class -> its mover, compiled on first use (most classes never recur)."""

    def __missing__(self, cls: type) -> _Mover:
        mover = _move_items if cls is tuple else _compile(cls)
        self[cls] = mover
        return mover


_MOVERS = _Movers()


def movable(line: A.Line) -> bool:
    """Whether `moved` may copy `line` (it has no parse issue)."""
    return not line.issues


def moved(line: A.Line, lineno: int, number: int | None, same: int | None = None) -> A.Line:
    """`line` (its text's tree, without parse issues) as text line `lineno`, with step
    number `number` (written with as many digits as `line`'s own), or `same` when `number`
    is None."""
    new = _new_object(A.Line)
    d = new.__dict__
    s = line.__dict__
    d.update(s)
    span = s["span"]
    d["span"] = _new_tuple(A.Span, (lineno, span[1], lineno, span[3]))
    d["number"] = same if number is None else number
    statement = s["statement"]
    if statement is not None:
        d["statement"] = _MOVERS[statement.__class__](statement, lineno)
    span = s["number_span"]
    if span is not None:
        d["number_span"] = _new_tuple(A.Span, (lineno, span[1], lineno, span[3]))
    span = s["label_span"]
    if span is not None:
        d["label_span"] = _new_tuple(A.Span, (lineno, span[1], lineno, span[3]))
    return new


__all__ = ["movable", "moved"]
