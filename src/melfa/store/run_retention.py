"""Which recorded runs keep their samples: old runs are thinned as workspace autosaves are
(one rule, `melfa.store.thinning.Retention`).

Per user, the newest `Retention.keep_recent` runs keep everything; older runs younger
than `Retention.hourly_for` keep their samples for the newest run of each hour, older
ones for the newest run of each day. A thinned run loses its samples (the replay) and its
simulated path, never its summary: who ran what, when, the fingerprint, how it ended, the
cycle times and the deviation stay for good (the record an instructor grades from).
A run marked ``kept`` is never thinned.

Pure: no I/O; the store applies it in the transaction that saves a run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime

from melfa.store.thinning import Retention, thinned

RUN_RETENTION = Retention(keep_recent=20)
"""The newest 20 runs of a user kept whole; older ones the newest of each hour for a week,
then of each day."""


@dataclass(frozen=True, slots=True)
class RunAge:
    """What thinning needs to know of one run that still has its samples."""

    id: int
    started: datetime
    kept: bool = False


def to_thin(runs: Sequence[RunAge], now: datetime, policy: Retention) -> list[int]:
    """The ids of ``runs`` (one user's, any order) whose samples go.

    >>> from datetime import UTC, timedelta
    >>> day = datetime(2026, 11, 1, tzinfo=UTC)
    >>> runs = [RunAge(i, day + timedelta(minutes=10 * i)) for i in range(8)]
    >>> to_thin(runs, day + timedelta(days=1), Retention(keep_recent=2))
    [4, 3, 2, 1, 0]
    """
    newest_first = sorted(runs, key=lambda r: (r.started, r.id), reverse=True)
    older = ((r.id, r.started) for r in newest_first[policy.keep_recent :] if not r.kept)
    return thinned(older, now, policy.hourly_for)


__all__ = ["RUN_RETENTION", "RunAge", "to_thin"]
