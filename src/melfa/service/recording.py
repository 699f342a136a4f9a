"""Every run on a shared robot, recorded from the state stream the service already has.

`RunRecorder` is told two things by its service (event loop only), and reads a third:

* a RUN the controller accepted (`RunRecorder.command_done`): a `Recording` begins, of who
  ran it and what the slot held then (`melfa.service.slot.Slot`, the service's one record
  of it, read through ``slot``: the fingerprint the instructor's gate compares, the step →
  line map of the student's own text, who loaded it; None: not known);
* every poll read (`RunRecorder.polled`) with the snapshot it made: one `Frame` each,
  timed on the service's clock; the first STATE read showing the program no longer running
  ends the recording (finished, stopped, or with an alarm), as do a lost link, the service
  closing, and `max_s`.

While a recording runs the service polls at its listening rate (``active``), whoever
watches. A finished recording goes to the ``sink`` (the web's stores it); nothing here
does I/O.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Callable
from dataclasses import dataclass, field

from melfa.lang.plan import UploadPlan
from melfa.service.clock import Clock
from melfa.service.events import Actor, LinkStatus, StateSnapshot, utc_now
from melfa.service.polling import PollResult, StateRead
from melfa.service.recording_frames import Frame
from melfa.service.slot import Slot
from melfa.vocab.commands import Command
from melfa.vocab.runs import RunOutcome

MAX_RUN_S = 1800.0
"""A run recorded longer than this ends its recording (a program looping for ever)."""


@dataclass
class Recording:
    """One run: who ran what, when, and every frame."""

    user: str
    started_at: dt.datetime
    """Wall time (UTC) the controller accepted RUN."""
    started: float
    """The same moment on the service's clock."""
    loaded: Slot | None
    """What the slot held when it began (None: not known)."""
    frames: list[Frame] = field(default_factory=list)
    outcome: RunOutcome | None = None
    ended: float | None = None

    @property
    def duration(self) -> float:
        return 0.0 if self.ended is None else self.ended - self.started

    @property
    def cycle_time(self) -> float | None:
        """RUN to the STATE read that showed the end, for a run that finished."""
        return self.duration if self.outcome is RunOutcome.FINISHED else None

    @property
    def fingerprint(self) -> str | None:
        return self.loaded.fingerprint if self.loaded is not None else None


Sink = Callable[[Recording], None]


class RunRecorder:
    """Records the runs of one service (see the module doc)."""

    def __init__(
        self,
        clock: Clock,
        sink: Sink,
        *,
        slot: Callable[[], Slot | None] = lambda: None,
        wall: Callable[[], dt.datetime] = utc_now,
        max_s: float = MAX_RUN_S,
    ) -> None:
        self._clock = clock
        self._sink = sink
        self._slot = slot
        self._wall = wall
        self.max_s = max_s
        self.current: Recording | None = None

    @property
    def active(self) -> bool:
        return self.current is not None

    # ------------------------------------------------------------------ what happened

    def command_done(
        self, actor: Actor, command: Command, plan: UploadPlan | None, ok: bool
    ) -> None:
        """A command ended (``ok``): a RUN begins a recording of what the slot holds."""
        if command is Command.RUN and ok:
            self._begin(actor)

    def polled(self, result: PollResult, snapshot: StateSnapshot) -> None:
        """A poll read made ``snapshot``: a frame; a STATE read may end the run."""
        run = self.current
        if run is None:
            return
        now = self._clock.now()
        run.frames.append(self._frame(run, snapshot, now))
        if isinstance(result, StateRead) and not result.program_running:
            if result.alarm is not None:
                outcome = RunOutcome.ALARM
            elif result.paused:
                outcome = RunOutcome.STOPPED
            else:
                outcome = RunOutcome.FINISHED
            self._end(outcome, now)
        elif now - run.started > self.max_s:
            self._end(RunOutcome.TOO_LONG, now)

    def link_changed(self, status: LinkStatus) -> None:
        if status is not LinkStatus.CONNECTED and self.current is not None:
            self._end(RunOutcome.LINK_LOST, self._clock.now())

    def close(self) -> None:
        """The service closes: a run under way ends here."""
        if self.current is not None:
            self._end(RunOutcome.SERVICE_CLOSED, self._clock.now())

    # ------------------------------------------------------------------ internals

    def _begin(self, actor: Actor) -> None:
        now = self._clock.now()
        if self.current is not None:
            self._end(RunOutcome.STOPPED, now)  # started again before a STATE saw it end
        self.current = Recording(actor.user, self._wall(), now, self._slot())

    def _frame(self, run: Recording, s: StateSnapshot, now: float) -> Frame:
        lines = run.loaded.step_lines if run.loaded is not None else {}
        return Frame(
            round(now - run.started, 3),
            s.joints,
            s.pose,
            line=lines.get(s.line) if s.line is not None else None,
            step=s.line,
            hands=s.hands,
            alarm=s.alarm.number if s.alarm is not None else None,
            override=s.override,
            servo=s.servo,
            running=bool(s.program_running),
            paused=bool(s.paused),
            moving=s.moving,
        )

    def _end(self, outcome: RunOutcome, now: float) -> None:
        run = self.current
        if run is None:
            return
        self.current = None
        run.outcome = outcome
        run.ended = now
        self._sink(run)


__all__ = ["MAX_RUN_S", "Recording", "RunRecorder", "Sink"]
