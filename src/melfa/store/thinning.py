"""How the store thins what it keeps as it ages, one rule for workspace autosaves
(`melfa.store.revisions`) and recorded runs (`melfa.store.run_retention`): past the newest
ones kept whole, the newest of each hour is kept while younger than a span, then the newest
of each day. Pure: no I/O.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from datetime import datetime, timedelta


@dataclass(frozen=True, slots=True)
class Retention:
    """How the store thins one kind of item as it ages (the rule above):
    `melfa.store.revisions.AUTOSAVE_RETENTION`, `melfa.store.run_retention.RUN_RETENTION`."""

    keep_recent: int
    """The newest items of their owner (a workspace's autosaves, a user's runs), all kept."""
    hourly_for: timedelta = timedelta(days=7)
    """Older items younger than this keep the newest of each hour; older still, of each day."""


def thinned(
    newest_first: Iterable[tuple[int, datetime]], now: datetime, hourly_for: timedelta
) -> list[int]:
    """The ids of the items, newest first past those kept whole, that go: all but the
    newest of each hour (items younger than ``hourly_for``) or of each day (older ones).

    >>> from datetime import UTC
    >>> day = datetime(2026, 11, 1, tzinfo=UTC)
    >>> items = [(i, day + timedelta(minutes=20 * i)) for i in reversed(range(6))]
    >>> thinned(items, day + timedelta(hours=3), timedelta(days=1))
    [4, 3, 1, 0]
    """
    seen: set[str] = set()
    doomed: list[int] = []
    for item, created in newest_first:
        hourly = now - created < hourly_for
        bucket = created.strftime("%Y-%m-%dT%H" if hourly else "%Y-%m-%d")
        if bucket in seen:
            doomed.append(item)
        else:
            seen.add(bucket)
    return doomed


__all__ = ["Retention", "thinned"]
