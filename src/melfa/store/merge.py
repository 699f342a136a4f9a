"""Three-way merge of two edits of one text, line by line, that never drops a line.

Issue 26: partners lost each other's lines to a dialog (*Keep mine* dropped bob's line) or
to no dialog at all. A save made on an older revision (the desktop client, the REST API, a
tab that was offline) is merged here with what was saved meanwhile instead of being
refused or overwriting it:

* a stretch of lines that only one side changed takes that side's lines;
* a stretch both sides changed the same way is taken once;
* a stretch both changed differently keeps both: the lines saved meanwhile first, then the
  incoming ones. Nothing either side wrote is lost; the student tidies it in the editor.

Pure: no I/O. `edit_script` turns one text into another as the few character edits a
shared document (the CRDT) applies, so a merged save reaches the live editors as an edit
of the lines it changed, not as a new document.
"""

from __future__ import annotations

from dataclasses import dataclass
from difflib import SequenceMatcher

__all__ = ["Splice", "edit_script", "merge3"]


@dataclass(frozen=True, slots=True)
class _Hunk:
    """Lines ``start:end`` of the base replaced by ``lines``."""

    start: int
    end: int
    lines: list[str]


def _hunks(base: list[str], other: list[str]) -> list[_Hunk]:
    matcher = SequenceMatcher(None, base, other, autojunk=False)
    return [
        _Hunk(i1, i2, other[j1:j2])
        for tag, i1, i2, j1, j2 in matcher.get_opcodes()
        if tag != "equal"
    ]


def _lines(text: str) -> list[str]:
    """Lines with their ends kept, so joining gives the text back exactly."""
    return text.splitlines(keepends=True)


def merge3(base: str, ours: str, theirs: str) -> str:
    """``base`` edited into ``ours`` (what is saved now) and into ``theirs`` (what arrives),
    both edits applied. Where both changed the same stretch differently, ours comes first,
    then theirs: no line is dropped."""
    if ours == theirs or theirs == base:
        return ours
    if ours == base:
        return theirs
    old = _lines(base)
    a_lines, b_lines = _lines(ours), _lines(theirs)
    # A last line without its end: give both sides one, so "x" and "x\n" match as lines.
    a_open = bool(a_lines) and not a_lines[-1].endswith("\n")
    b_open = bool(b_lines) and not b_lines[-1].endswith("\n")
    old, a_lines, b_lines = (_closed(x) for x in (old, a_lines, b_lines))
    ours_h, theirs_h = _hunks(old, a_lines), _hunks(old, b_lines)
    out: list[str] = []
    pos = 0
    i = j = 0
    while i < len(ours_h) or j < len(theirs_h):
        # The next group: hunks of either side that overlap (or touch at one point).
        first = _earliest(ours_h, i, theirs_h, j)
        start, end = first.start, first.end
        group_a: list[_Hunk] = []
        group_b: list[_Hunk] = []
        grew = True
        while grew:
            grew = False
            while i < len(ours_h) and _touches(ours_h[i], start, end):
                end = max(end, ours_h[i].end)
                group_a.append(ours_h[i])
                i += 1
                grew = True
            while j < len(theirs_h) and _touches(theirs_h[j], start, end):
                end = max(end, theirs_h[j].end)
                group_b.append(theirs_h[j])
                j += 1
                grew = True
        out.extend(old[pos:start])
        side_a = _apply(old, start, end, group_a)
        side_b = _apply(old, start, end, group_b)
        if not group_b or side_a == side_b:
            out.extend(side_a)
        elif not group_a:
            out.extend(side_b)
        else:
            out.extend(side_a)
            out.extend(line for line in side_b if line not in side_a)
        pos = end
    out.extend(old[pos:])
    merged = "".join(out)
    if a_open and b_open and merged.endswith("\n"):
        merged = merged[:-1]
    return merged


def _closed(lines: list[str]) -> list[str]:
    if lines and not lines[-1].endswith("\n"):
        return [*lines[:-1], lines[-1] + "\n"]
    return lines


def _earliest(a: list[_Hunk], i: int, b: list[_Hunk], j: int) -> _Hunk:
    """The next hunk of either side; at one line, an insertion before a replacement."""
    if j >= len(b) or (i < len(a) and (a[i].start, a[i].end) <= (b[j].start, b[j].end)):
        return a[i]
    return b[j]


def _touches(hunk: _Hunk, start: int, end: int) -> bool:
    """Changes lines of the stretch, or inserts inside it, or inserts where the stretch is
    itself an insertion (two people adding lines at one place: both kept, in one group).
    Changes that only meet at an edge are applied apart."""
    if hunk.start == hunk.end:
        return start < hunk.start < end or start == end == hunk.start
    return hunk.start < end and start < hunk.end


def _apply(old: list[str], start: int, end: int, hunks: list[_Hunk]) -> list[str]:
    """The stretch ``old[start:end]`` with one side's hunks applied."""
    out: list[str] = []
    pos = start
    for hunk in hunks:
        out.extend(old[pos : hunk.start])
        out.extend(hunk.lines)
        pos = hunk.end
    out.extend(old[pos:end])
    return out


@dataclass(frozen=True, slots=True)
class Splice:
    """At character ``index``, delete ``delete`` characters, then insert ``insert``."""

    index: int
    delete: int
    insert: str


def edit_script(old: str, new: str) -> list[Splice]:
    """The character edits that turn ``old`` into ``new``, last first (each index is valid
    when applied in this order), found line by line then within the changed lines."""
    if old == new:
        return []
    a, b = _lines(old), _lines(new)
    splices: list[Splice] = []
    offsets = [0]
    for line in a:
        offsets.append(offsets[-1] + len(line))
    matcher = SequenceMatcher(None, a, b, autojunk=False)
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        before = "".join(a[i1:i2])
        after = "".join(b[j1:j2])
        # Trim what the changed stretch keeps at its ends, so a changed line is a small edit.
        head = 0
        while head < min(len(before), len(after)) and before[head] == after[head]:
            head += 1
        tail = 0
        while (
            tail < min(len(before), len(after)) - head
            and before[len(before) - 1 - tail] == after[len(after) - 1 - tail]
        ):
            tail += 1
        splices.append(
            Splice(
                offsets[i1] + head,
                len(before) - head - tail,
                after[head : len(after) - tail],
            )
        )
    return splices[::-1]
