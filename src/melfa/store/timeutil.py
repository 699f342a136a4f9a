"""Times in the database: UTC, fixed-width ISO 8601 text, so text order is time order.

>>> to_text(datetime(2024, 9, 1, 8, 30, tzinfo=UTC))
'2024-09-01T08:30:00.000000Z'
>>> from_text('2024-09-01T08:30:00.000000Z')
datetime.datetime(2024, 9, 1, 8, 30, tzinfo=datetime.timezone.utc)
"""

from __future__ import annotations

from collections.abc import Callable
from datetime import UTC, datetime

__all__ = ["Clock", "from_text", "from_text_or_none", "system_clock", "to_text"]

Clock = Callable[[], datetime]
"""Returns the current time, timezone-aware. Injected so tests control expiry."""

_FORMAT = "%Y-%m-%dT%H:%M:%S.%fZ"


def system_clock() -> datetime:
    """The real time in UTC."""
    return datetime.now(UTC)


def to_text(moment: datetime) -> str:
    """A timezone-aware time as sortable UTC text; naive times are our misuse."""
    if moment.tzinfo is None:
        raise ValueError("naive datetime given to the store; pass a timezone-aware time")
    return moment.astimezone(UTC).strftime(_FORMAT)


def from_text(text: str) -> datetime:
    """The inverse of `to_text`."""
    return datetime.strptime(text, _FORMAT).replace(tzinfo=UTC)


def from_text_or_none(text: str | None) -> datetime | None:
    return None if text is None else from_text(text)
