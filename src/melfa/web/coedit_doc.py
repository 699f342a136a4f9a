"""A shared workspace's live document on the server: the program and the points as two
texts of one CRDT (pycrdt, the Python peer of the browsers' Yjs), and the merges of text
that arrives from elsewhere (a save through the API, a restore, an imported file).

The CRDT merges concurrent keystrokes by itself: two people typing on two lines, or one
typing offline for half a minute, both keep every character. Text from outside the CRDT
(the desktop client saves whole texts on a revision) is merged line by line against what
it was based on (`melfa.store.merge.merge3`) and enters the document as the few
character edits that make the difference (`edit_script`), so open editors see a partner's
edit, not a new document.

No I/O and no clock: `web.coedit` owns the sockets, the saving and the timing.
"""

from __future__ import annotations

from dataclasses import dataclass

from pycrdt import Doc, Text

from melfa.store.merge import edit_script, merge3

__all__ = ["POINTS", "PROGRAM", "Contents", "SharedDoc"]

PROGRAM = "program"
POINTS = "points"


@dataclass(frozen=True, slots=True)
class Contents:
    """A workspace's two texts."""

    program: str
    points: str


class SharedDoc:
    """One workspace's CRDT document. Updates are Yjs v1 updates, as the browsers send."""

    def __init__(self, state: bytes | None = None) -> None:
        self.doc: Doc[Text] = Doc()
        self.program = self.doc.get(PROGRAM, type=Text)
        self.points = self.doc.get(POINTS, type=Text)
        if state:
            self.doc.apply_update(state)

    @property
    def contents(self) -> Contents:
        return Contents(str(self.program), str(self.points))

    def state(self) -> bytes:
        """Everything, as one update (what is stored)."""
        return self.doc.get_update()

    def state_vector(self) -> bytes:
        return self.doc.get_state()

    def missing(self, state_vector: bytes) -> bytes:
        """What a peer whose document is at ``state_vector`` lacks."""
        return self.doc.get_update(state_vector)

    def apply(self, update: bytes) -> bool:
        """Apply a peer's update; whether the text changed (an update may hold nothing new,
        or only what this document already has). Compared by text: a deletion adds no
        item, so the state vector alone would miss it."""
        before = self.contents
        self.doc.apply_update(update)
        return self.contents != before

    def edit_to(self, target: Contents) -> bytes | None:
        """Make the texts ``target`` with the fewest character edits; the update that does
        it (to send to every peer), or None when nothing changed."""
        if self.contents == target:
            return None
        before = self.state_vector()
        with self.doc.transaction():
            _splice(self.program, target.program)
            _splice(self.points, target.points)
        # From the old state vector: the new items, and the whole delete set (deletions).
        return self.doc.get_update(before)

    def merge_in(self, base: Contents, theirs: Contents) -> bytes | None:
        """Someone edited ``base`` into ``theirs`` outside the document: apply that edit to
        what the document holds now (line by line, no line dropped); the update, or None."""
        now = self.contents
        merged = Contents(
            merge3(base.program, now.program, theirs.program),
            merge3(base.points, now.points, theirs.points),
        )
        return self.edit_to(merged)


def _splice(text: Text, target: str) -> None:
    """Edit ``text`` into ``target``. pycrdt counts positions in UTF-8 bytes (Yjs in UTF-16
    units): the character positions of `edit_script` are converted here."""
    current = str(text)
    for splice in edit_script(current, target):  # last first: earlier indexes stay valid
        at = len(current[: splice.index].encode())
        if splice.delete:
            end = at + len(current[splice.index : splice.index + splice.delete].encode())
            del text[at:end]
        if splice.insert:
            text.insert(at, splice.insert)
