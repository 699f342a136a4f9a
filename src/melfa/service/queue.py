"""The fair queue for one shared robot (the lab's arm): pure logic, no I/O, no clock.

Every method takes ``now`` (seconds on the wall clock, so a stored queue means the same
after a restart) and returns the `Step`s it made; `melfa.service.queue_keeper` runs it
against the service (the lease, STOP, the audit, the store, the live messages).

The rules (issue 22):

- Students enter with a text that passed the policy (`Policy.may_queue`); entering again
  replaces the text and keeps the place, until the turn starts.
- While nobody is at the arm and the queue is not paused, the head is **offered** the arm
  for `QueueSettings.claim_s`. A claim starts the **turn** (`turn_s`), and the lease is
  theirs. A missed claim moves them back **one** place, not out.
- A turn is warned `warn_s` before its end; at its end a running program is stopped, or
  allowed to finish (`TurnEnd.FINISH`, up to `finish_cap_s`) while nothing new starts; then
  the next is offered.
- A student whose last connection closed keeps their place (and their turn) for
  `grace_s`; longer away, they leave the queue (their turn ends).
- The instructor pauses and resumes, moves a student, skips one, extends a turn, takes the
  arm at once (the queue pauses, the turn's time left is kept), switches attended mode
  (each run waits for *Arm ready*).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from melfa.vocab.queue import EntryState, QueueStep, TurnEnd
from melfa.vocab.refusals import Refusal

DOC_VERSION = 1


@dataclass(frozen=True)
class QueueSettings:
    """A lab's queue settings (seconds)."""

    claim_s: float = 60.0
    """How long the head has to claim the arm."""
    turn_s: float = 240.0
    """How long a turn lasts: load, run, watch, reset."""
    grace_s: float = 120.0
    """How long a student whose connection closed keeps their place."""
    warn_s: float = 30.0
    """How long before a turn's end the student is told."""
    at_turn_end: TurnEnd = TurnEnd.STOP
    finish_cap_s: float = 120.0
    """With `TurnEnd.FINISH`: how long past the end a program may still run."""
    overhead_s: float = 40.0
    """A turn's time beyond its pre-flight cycle time (claim, load, reset), for estimates."""

    def __post_init__(self) -> None:
        for name in ("claim_s", "turn_s", "grace_s", "overhead_s"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be positive")
        if not 0 <= self.warn_s < self.turn_s:
            raise ValueError("warn_s must be at least 0 and shorter than a turn")

    def expected(self, cycle_s: float | None) -> float:
        """A turn's expected length: its cycle time and the overhead, at most a turn."""
        if cycle_s is None:
            return self.turn_s
        return min(self.turn_s, self.overhead_s + cycle_s)


@dataclass
class Entry:
    """A student in the queue with the exact text that passed (program and points)."""

    user: str
    role: str
    program: str
    points: str
    program_digest: str
    points_digest: str
    cycle_s: float | None
    """The pre-flight cycle time (None: not known)."""
    joined: float
    workspace_id: int | None = None
    stale: bool = False
    away_since: float | None = None
    offered_until: float | None = None
    missed: int = 0
    gate: Refusal | None = None
    """What the instructor's gate would say to this text now (None: it would load): the
    cell was edited since it passed, or the gate switched on (`TurnQueue.gate_checked`)."""

    def __post_init__(self) -> None:
        if self.gate is not None:  # from the stored document: the refusal's wire value
            self.gate = Refusal(self.gate)

    @property
    def state(self) -> EntryState:
        return EntryState.WAITING if self.offered_until is None else EntryState.OFFERED


@dataclass
class Turn:
    """Who is at the arm, until when."""

    user: str
    role: str
    started: float
    ends: float
    entry: Entry | None = None
    """The text they queued (None: they held the arm when the queue began)."""
    warned: bool = False
    ending: bool = False
    """Time is up and the program finishes (`TurnEnd.FINISH`)."""
    away_since: float | None = None
    left_s: float | None = None
    """While an instructor holds the arm: the turn's time left, kept."""
    ready: bool = False
    """Attended mode: the supervisor said the arm is ready for the next run."""


@dataclass(frozen=True)
class Step:
    """One transition, for the audit and the live message."""

    kind: QueueStep
    user: str | None = None
    by: str | None = None
    position: int | None = None
    seconds: float | None = None
    stop: bool = False
    """The keeper must STOP the arm (a turn ended with the program running)."""

    def words(self) -> str:
        return self.kind.words(self.user, self.by, self.position, self.seconds)


class QueueError(Exception):
    """An operation the queue refuses (the keeper raises it as `Refused`)."""

    def __init__(self, reason: Refusal, user: str | None = None) -> None:
        super().__init__(reason.value)
        self.reason = reason
        self.user = user


@dataclass
class TurnQueue:
    """The queue of one shared robot (see the module doc)."""

    settings: QueueSettings = field(default_factory=QueueSettings)
    entries: list[Entry] = field(default_factory=list)
    turn: Turn | None = None
    paused: bool = False
    attended: bool = False

    # ------------------------------------------------------------------ queries

    @property
    def active(self) -> bool:
        """Whether the lease is given only by the queue (someone waits or is at the arm)."""
        return bool(self.entries) or self.turn is not None

    def find(self, user: str) -> Entry | None:
        return next((e for e in self.entries if e.user == user), None)

    def position(self, user: str) -> int | None:
        """1-based place in the line (None: not in it)."""
        for i, entry in enumerate(self.entries):
            if entry.user == user:
                return i + 1
        return None

    def at_arm(self, user: str) -> bool:
        return self.turn is not None and self.turn.user == user

    def estimates(self, now: float) -> list[float]:
        """When each entry's turn should start (same order as `entries`): after the
        current turn's time left, each one before it taking its expected length."""
        t = now
        turn = self.turn
        if turn is not None:
            t = now + turn.left_s if turn.left_s is not None else max(now, turn.ends)
        starts = []
        for entry in self.entries:
            if entry.offered_until is not None:
                t = max(t, now)
            starts.append(t)
            t += self.settings.expected(entry.cycle_s)
        return starts

    def next_deadline(self) -> float | None:
        """The next time something happens by itself (an offer runs out, a warning, a
        turn's end, a grace time)."""
        times: list[float] = []
        grace = self.settings.grace_s
        for entry in self.entries:
            if entry.offered_until is not None:
                times.append(entry.offered_until)
            if entry.away_since is not None:
                times.append(entry.away_since + grace)
        turn = self.turn
        if turn is not None and turn.left_s is None:
            if not turn.warned:
                times.append(turn.ends - self.settings.warn_s)
            times.append(turn.ends + (self.settings.finish_cap_s if turn.ending else 0.0))
            if turn.away_since is not None:
                times.append(turn.away_since + grace)
        return min(times) if times else None

    # ------------------------------------------------------------------ students

    def join(self, entry: Entry) -> list[Step]:
        """Enter the line at its end, or replace the text of the place one has."""
        old = self.find(entry.user)
        if old is not None:
            index = self.entries.index(old)
            self.entries[index] = dataclasses.replace(
                entry, joined=old.joined, offered_until=old.offered_until, missed=old.missed
            )
            return [Step(QueueStep.UPDATED, entry.user, position=index + 1)]
        self.entries.append(entry)
        return [Step(QueueStep.JOINED, entry.user, position=len(self.entries))]

    def leave(self, user: str) -> list[Step]:
        entry = self._entry(user)
        self.entries.remove(entry)
        return [Step(QueueStep.LEFT, user)]

    def claim(self, user: str, now: float) -> list[Step]:
        """The offered head takes the arm: their turn begins."""
        entry = self.find(user)
        if entry is None or entry.offered_until is None or self.turn is not None:
            raise QueueError(Refusal.NOT_YOUR_TURN, user)
        self.entries.remove(entry)
        entry.offered_until = None
        self.turn = Turn(user, entry.role, now, now + self.settings.turn_s, entry=entry)
        return [Step(QueueStep.CLAIMED, user)]

    def finish(self, user: str) -> list[Step]:
        """The student at the arm gives it back before the end."""
        if not self.at_arm(user):
            raise QueueError(Refusal.NOT_QUEUED, user)
        self.turn = None
        return [Step(QueueStep.FINISHED, user)]

    def adopt(self, user: str, role: str, now: float) -> list[Step]:
        """Someone held the arm when the queue began: that is their turn, of a turn's length."""
        if self.turn is None:
            self.turn = Turn(user, role, now, now + self.settings.turn_s)
        return []

    def workspace_saved(self, workspace_id: int, program: str, points: str) -> list[Step]:
        """A workspace was saved: entries queued from it whose text differs are stale."""
        steps = []
        for entry in self.entries:
            if entry.workspace_id != workspace_id:
                continue
            stale = (program, points) != (entry.program, entry.points)
            if stale != entry.stale:
                entry.stale = stale
                steps.append(Step(QueueStep.STALE if stale else QueueStep.FRESH, entry.user))
        return steps

    def gate_checked(self, refusal_of: Callable[[Entry], Refusal | None]) -> list[Step]:
        """The instructor's gate asked again about each queued text (``refusal_of``): an
        entry it would now refuse must pass pre-flight again before its turn comes, which
        its student is told at once rather than at the claim; one it lets through again is
        fine."""
        steps = []
        for entry in self.entries:
            gate = refusal_of(entry)
            if gate is entry.gate:
                continue
            entry.gate = gate
            if gate is None:
                kind = QueueStep.PREFLIGHT_OK
            elif gate is Refusal.CELL_CHANGED:
                kind = QueueStep.PREFLIGHT_AGAIN
            else:
                kind = QueueStep.PREFLIGHT_NEEDED
            steps.append(Step(kind, entry.user))
        return steps

    # ------------------------------------------------------------------ time

    def tick(self, now: float, connected: Callable[[str], bool], running: bool) -> list[Step]:
        """Everything due at ``now``: presence and grace, the turn's warning and end, the
        offer to the head and a missed claim. ``connected(user)``: an open connection;
        ``running``: the arm runs a program."""
        steps = self._presence(now, connected)
        steps += self._turn(now, running)
        steps += self._offer(now)
        return steps

    def _presence(self, now: float, connected: Callable[[str], bool]) -> list[Step]:
        steps: list[Step] = []
        grace = self.settings.grace_s
        for entry in list(self.entries):
            if connected(entry.user):
                if entry.away_since is not None:
                    entry.away_since = None
                    steps.append(Step(QueueStep.BACK, entry.user))
            elif entry.away_since is None:
                entry.away_since = now
                steps.append(Step(QueueStep.AWAY, entry.user))
            elif now >= entry.away_since + grace:
                self.entries.remove(entry)
                steps.append(Step(QueueStep.GONE, entry.user))
        turn = self.turn
        if turn is not None and turn.left_s is None:
            if connected(turn.user):
                if turn.away_since is not None:
                    turn.away_since = None
                    steps.append(Step(QueueStep.BACK, turn.user))
            elif turn.away_since is None:
                turn.away_since = now
                steps.append(Step(QueueStep.AWAY, turn.user))
            elif now >= turn.away_since + grace:
                self.turn = None
                steps.append(Step(QueueStep.GONE, turn.user, stop=True))
        return steps

    def _turn(self, now: float, running: bool) -> list[Step]:
        turn = self.turn
        if turn is None or turn.left_s is not None:
            return []
        settings = self.settings
        if not turn.warned and now >= turn.ends - settings.warn_s and now < turn.ends:
            turn.warned = True
            return [Step(QueueStep.WARNED, turn.user, seconds=turn.ends - now)]
        if now < turn.ends:
            return []
        finish = settings.at_turn_end is TurnEnd.FINISH
        if running and finish and now < turn.ends + settings.finish_cap_s:
            if turn.ending:
                return []
            turn.ending = True
            return [Step(QueueStep.ENDING, turn.user)]
        self.turn = None
        kind = QueueStep.STOPPED if running else QueueStep.ENDED
        return [Step(kind, turn.user, stop=running)]

    def _offer(self, now: float) -> list[Step]:
        if self.paused or self.turn is not None or not self.entries:
            return []
        steps: list[Step] = []
        head = self.entries[0]
        if head.offered_until is not None and now >= head.offered_until:
            head.offered_until = None
            head.missed += 1
            if len(self.entries) > 1:
                self.entries[0], self.entries[1] = self.entries[1], head
            steps.append(Step(QueueStep.MISSED, head.user, position=self.position(head.user)))
            head = self.entries[0]
        if head.offered_until is None:
            head.offered_until = now + self.settings.claim_s
            steps.append(Step(QueueStep.OFFERED, head.user, seconds=self.settings.claim_s))
        return steps

    # ------------------------------------------------------------------ the instructor

    def pause(self, by: str) -> list[Step]:
        if self.paused:
            return []
        self.paused = True
        for entry in self.entries:
            entry.offered_until = None
        return [Step(QueueStep.PAUSED, by=by)]

    def resume(self, by: str, now: float) -> list[Step]:
        """Go on: a turn kept while an instructor held the arm continues with its time left."""
        if not self.paused:
            return []
        self.paused = False
        turn = self.turn
        if turn is not None and turn.left_s is not None:
            turn.ends = now + turn.left_s
            turn.left_s = None
            turn.warned = turn.ends - self.settings.warn_s <= now
        return [Step(QueueStep.RESUMED, by=by), *self._offer(now)]

    def move(self, user: str, position: int, by: str) -> list[Step]:
        """Put ``user`` at ``position`` (1-based, clamped); an open offer is withdrawn."""
        entry = self._entry(user)
        self.entries.remove(entry)
        index = max(0, min(position - 1, len(self.entries)))
        self.entries.insert(index, entry)
        for other in self.entries:
            other.offered_until = None
        return [Step(QueueStep.MOVED, user, by, position=index + 1)]

    def skip(self, user: str, by: str, now: float) -> list[Step]:
        """Out of the queue; at the arm, their turn ends (a running program is stopped)."""
        if self.at_arm(user):
            self.turn = None
            return [Step(QueueStep.SKIPPED, user, by, stop=True)]
        entry = self._entry(user)
        self.entries.remove(entry)
        return [Step(QueueStep.SKIPPED, user, by)]

    def extend(self, seconds: float, by: str) -> list[Step]:
        turn = self.turn
        if turn is None:
            raise QueueError(Refusal.NOT_QUEUED)
        if turn.left_s is not None:
            turn.left_s += seconds
        else:
            turn.ends += seconds
            turn.ending = False
            turn.warned = False
        return [Step(QueueStep.EXTENDED, turn.user, by, seconds=seconds)]

    def take(self, by: str, now: float) -> list[Step]:
        """An instructor takes the arm at once: the queue pauses; a turn keeps its time."""
        steps = self.pause(by)
        turn = self.turn
        if turn is not None and turn.left_s is None and turn.user != by:
            turn.left_s = max(0.0, turn.ends - now)
        return [Step(QueueStep.TAKEN, by=by), *steps]

    def set_attended(self, on: bool, by: str) -> list[Step]:
        if self.attended == on:
            return []
        self.attended = on
        return [Step(QueueStep.ATTENDED_ON if on else QueueStep.ATTENDED_OFF, by=by)]

    def _entry(self, user: str) -> Entry:
        entry = self.find(user)
        if entry is None:
            raise QueueError(Refusal.NOT_QUEUED, user)
        return entry

    # ------------------------------------------------------------------ storing

    def to_doc(self) -> dict[str, Any]:
        """Everything but the settings, as JSON (the store keeps it)."""
        return {
            "version": DOC_VERSION,
            "entries": [dataclasses.asdict(e) for e in self.entries],
            "turn": None if self.turn is None else _turn_doc(self.turn),
            "paused": self.paused,
            "attended": self.attended,
        }

    @classmethod
    def from_doc(cls, doc: dict[str, Any], settings: QueueSettings) -> TurnQueue:
        if doc.get("version") != DOC_VERSION:
            return cls(settings)
        turn = doc.get("turn")
        return cls(
            settings,
            [Entry(**e) for e in doc.get("entries", [])],
            None if turn is None else _turn_from(turn),
            bool(doc.get("paused")),
            bool(doc.get("attended")),
        )


def _turn_doc(turn: Turn) -> dict[str, Any]:
    return dataclasses.asdict(turn)


def _turn_from(doc: dict[str, Any]) -> Turn:
    fields = dict(doc)
    entry = fields.pop("entry", None)
    return Turn(**fields, entry=None if entry is None else Entry(**entry))


__all__ = ["DOC_VERSION", "Entry", "QueueError", "QueueSettings", "Step", "Turn", "TurnQueue"]
