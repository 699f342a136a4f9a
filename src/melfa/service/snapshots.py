"""The service's one `StateSnapshot`: every change makes a new one (numbered, stamped,
with the lease, the jog and the activity worked out again) and publishes it.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable

from melfa.service.bus import EventBus
from melfa.service.events import LinkStatus, StateSnapshot
from melfa.service.lease import Lease
from melfa.vocab.activity import Activity, Facts, Motion, activity_of

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

    def update(self, change: Change | None = None) -> StateSnapshot:
        """Apply ``change`` (a typed replace; None: only lease, jog and activity), publish."""
        info = self._lease.info()
        jog = self._jog_label()
        base = change(self.latest) if change is not None else self.latest
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


__all__ = ["Change", "Snapshots"]
