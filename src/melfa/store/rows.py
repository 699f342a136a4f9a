"""How a row of the database becomes one of the store's records: each field of the record
(a dataclass) read from the row's column of the same name, through a converter where the
column's form differs (text times, enum values, 0/1 flags). One home for that step, so a
record and its query cannot drift apart field by field.

>>> import sqlite3
>>> from dataclasses import dataclass
>>> @dataclass
... class Point:
...     name: str
...     visible: bool
>>> conn = sqlite3.connect(":memory:")
>>> conn.row_factory = sqlite3.Row
>>> row = conn.execute("SELECT 'P1' AS name, 1 AS visible, 7 AS unused").fetchone()
>>> record(Point, row, visible=bool)
Point(name='P1', visible=True)
"""

from __future__ import annotations

import sqlite3
from collections.abc import Callable
from dataclasses import fields
from functools import cache
from typing import TYPE_CHECKING, Any, TypeVar

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

Record = TypeVar("Record", bound="DataclassInstance")


@cache
def _field_names(kind: type[DataclassInstance]) -> tuple[str, ...]:
    return tuple(f.name for f in fields(kind) if f.init)


def record(kind: type[Record], row: sqlite3.Row, **convert: Callable[[Any], object]) -> Record:
    """A ``kind`` from ``row``: every field from its column, through ``convert[field]``
    where given; columns the record has no field for are left alone."""
    return kind(
        **{
            name: convert[name](row[name]) if name in convert else row[name]
            for name in _field_names(kind)
        }
    )


__all__ = ["record"]
