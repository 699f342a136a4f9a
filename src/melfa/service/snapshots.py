"""The service's one `StateSnapshot`: every change makes a new one (numbered, stamped,
with the lease, the jog and the activity worked out again) and publishes it.

It also keeps the note of the motion melfa last started (`melfa.vocab.activity.Motion`),
moved on by the STATE reads (`update` with ``state_read``), and names the line of a
run-time error: an alarm that comes while the program runs is the program's, at the step
the controller reports, mapped to the loaded text's line through the slot's step map.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable

from melfa.service.bus import EventBus
from melfa.service.events import Alarm, LinkStatus, StateSnapshot
from melfa.service.lease import Lease
from melfa.vocab.activity import Activity, Facts, Motion, MotionKind, MotionPhase, activity_of

Change = Callable[[StateSnapshot], StateSnapshot]


class Snapshots:
    """Holds the latest snapshot (event loop only)."""

    def __init__(self, bus: EventBus, lease: Lease, jog_label: Callable[[], str | None]) -> None:
        self._bus = bus
        self._lease = lease
        self._jog_label = jog_label
        """The label of the jog under way, None when nobody jogs."""
        self._seq = itertools.count(1)
        self.latest = StateSnapshot()
        self.motion: Motion | None = None
        """The motion the service last started (names the activity while it moves)."""

    def motion_sent(self, motion: Motion) -> None:
        """The controller took ``motion`` (if it is still the latest): the next STATE read
        tells whether it moves or is already over."""
        if self.motion is motion and motion.phase is MotionPhase.ASKED:
            self.motion = Motion(motion.kind, motion.label, MotionPhase.SENT)

    def motion_ended(self) -> None:
        """A STOP, or the motion's command failed: no motion of melfa's is under way."""
        self.motion = None

    def update(self, change: Change | None = None, *, state_read: bool = False) -> StateSnapshot:
        """Apply ``change`` (a typed replace; None: only lease, jog and activity), publish.
        ``state_read``: the change is a STATE read (it moves the motion's phase on)."""
        info = self._lease.info()
        jog = self._jog_label()
        before = self.latest
        base = change(before) if change is not None else before
        motion = self.motion
        ran = motion is not None and motion.kind is MotionKind.RUN
        ran = ran and motion is not None and motion.phase is not MotionPhase.ARRIVED
        base = dataclasses.replace(base, alarm=_program_error(before, base, ran))
        if jog is not None and self.motion is not None and self.motion.phase is MotionPhase.ARRIVED:
            self.motion = None  # a jog moved the arm off the point
        if state_read and self.motion is not None:
            self.motion = self.motion.after_state_read(bool(base.running or base.moving))
        snapshot = dataclasses.replace(
            base,
            seq=next(self._seq),
            at=type(base.at).now(base.at.tzinfo),
            jogging=jog is not None,
            lease_holder=info.holder.user if info.holder is not None else None,
            lease_since=info.since,
            lease_state=info.state.value if info.state is not None else None,
        )
        facts = Facts(
            connected=snapshot.link is LinkStatus.CONNECTED,
            busy=snapshot.busy,
            alarm=snapshot.alarm is not None,
            jogging=snapshot.jogging,
            running=snapshot.running,
            program_running=snapshot.program_running,
            paused=snapshot.paused,
            moving=snapshot.moving,
            line=snapshot.line,
        )
        activity, detail = activity_of(facts, self.motion)
        if activity is Activity.JOGGING and jog is not None:
            detail = jog
        self.latest = dataclasses.replace(snapshot, activity=activity, activity_detail=detail)
        self._bus.publish(self.latest)
        return self.latest


def _program_error(before: StateSnapshot, after: StateSnapshot, ran: bool) -> Alarm | None:
    """``after``'s alarm, naming the program's step and the loaded text's line when it came
    while the program ran (``ran``: melfa started it and it has not been seen to end), kept
    as long as the same alarm stays."""
    alarm = after.alarm
    if alarm is None or alarm.step is not None:
        return alarm
    old = before.alarm
    if old is not None and old.number == alarm.number and old.step is not None:
        return dataclasses.replace(alarm, step=old.step, line=old.line)
    was_running = old is None and bool(before.program_running or before.running or ran)
    if not was_running or not after.line:
        return alarm
    slot = after.slot
    return dataclasses.replace(
        alarm, step=after.line, line=slot.line_of(after.line) if slot is not None else None
    )


__all__ = ["Change", "Snapshots"]
