"""Which recorded runs keep their samples: old runs are thinned as workspace autosaves are
(`melfa.store.revisions.RetentionPolicy`; one rule, `melfa.store.thinning`).

Per user, the newest `RunRetention.keep_recent` runs keep everything; older runs younger
than `RunRetention.hourly_for` keep their samples for the newest run of each hour, older
ones for the newest run of each day. A thinned run loses its samples (the replay) and its
simulated path, never its summary: who ran what, when, the fingerprint, how it ended, the
cycle times and the deviation stay for good (the record an instructor grades from).
A run marked ``kept`` is never thinned.

Pure: no I/O; the store applies it in the transaction that saves a run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime, timedelta

from melfa.store.thinning import thinned


@dataclass(frozen=True, slots=True)
class RunRetention:
    keep_recent: int = 20
    """The newest runs of a user, all kept whole."""
    hourly_for: timedelta = timedelta(days=7)
    """Older runs younger than this: the newest of each hour keeps its samples."""
    # Older still: the newest of each day.


@dataclass(frozen=True, slots=True)
class RunAge:
    """What thinning needs to know of one run that still has its samples."""

    id: int
    started: datetime
    kept: bool = False


def to_thin(runs: Sequence[RunAge], now: datetime, policy: RunRetention) -> list[int]:
    """The ids of ``runs`` (one user's, any order) whose samples go.

    >>> from datetime import UTC
    >>> day = datetime(2026, 11, 1, tzinfo=UTC)
    >>> runs = [RunAge(i, day + timedelta(minutes=10 * i)) for i in range(8)]
    >>> to_thin(runs, day + timedelta(days=1), RunRetention(keep_recent=2))
    [4, 3, 2, 1, 0]
    """
    newest_first = sorted(runs, key=lambda r: (r.started, r.id), reverse=True)
    older = ((r.id, r.started) for r in newest_first[policy.keep_recent :] if not r.kept)
    return thinned(older, now, policy.hourly_for)


__all__ = ["RunAge", "RunRetention", "to_thin"]
