"""`melfa.lang.record.Record` behaves as the frozen dataclasses it replaced."""

from __future__ import annotations

import copy
import pickle

import pytest

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Diagnostic, Severity
from melfa.lang.record import FrozenError, Record, field


class Pair(Record):
    a: int
    b: str = "x"
    note: str = field(default="", compare=False)


class Bag(Record, frozen=False):
    items: list[int] = field(default_factory=list)
    count: int = 0


class Checked(Record):
    value: int

    def __post_init__(self) -> None:
        if self.value < 0:
            raise ValueError("negative")


def test_fields_defaults_and_keywords() -> None:
    assert Pair(1) == Pair(a=1, b="x")
    assert Pair(1, "y").b == "y"
    assert Pair.__match_args__ == ("a", "b", "note")  # type: ignore[attr-defined]
    with pytest.raises(TypeError):
        Pair()  # type: ignore[call-arg]
    with pytest.raises(TypeError):
        Pair(1, "y", "n", "extra")  # type: ignore[call-arg]


def test_equality_and_hash_ignore_uncompared_fields() -> None:
    assert Pair(1, note="a") == Pair(1, note="b")
    assert hash(Pair(1, note="a")) == hash(Pair(1, note="b"))
    assert Pair(1) != Pair(2)
    assert A.Goto(A.LineRef(1, A.Span(1, 1, 1, 2)), A.Span(1, 1, 1, 2)) != A.Gosub(
        A.LineRef(1, A.Span(1, 1, 1, 2)), A.Span(1, 1, 1, 2)
    )  # same fields, different classes: not equal (as dataclasses)


def test_frozen_by_default() -> None:
    pair = Pair(1)
    with pytest.raises(FrozenError):
        pair.a = 2  # type: ignore[misc]
    with pytest.raises(AttributeError):
        del pair.a  # type: ignore[misc]


def test_mutable_records_get_fresh_defaults_and_no_hash() -> None:
    first, second = Bag(), Bag()
    first.items.append(1)
    first.count = 3
    assert second.items == [] and first == Bag([1], 3)
    with pytest.raises(TypeError):
        hash(first)


def test_post_init_runs() -> None:
    with pytest.raises(ValueError, match="negative"):
        Checked(-1)
    with pytest.raises(ValueError):
        Diagnostic(0, 1, 1, 1, Severity.ERROR, "m", "r")


def test_repr_pickle_and_copy() -> None:
    name = A.Name("PA", A.Span(1, 5, 1, 7), "Pa")
    assert (
        repr(name)
        == "Name(name='PA', span=Span(line=1, column=5, end_line=1, end_column=7), text='Pa')"
    )
    assert pickle.loads(pickle.dumps(name)) == name
    assert copy.deepcopy(name).text == "Pa"


def test_non_default_after_default_is_refused() -> None:
    with pytest.raises(TypeError, match="follows a default"):

        class Bad(Record):
            a: int = 0
            b: int


def test_a_subclass_of_a_record_already_used_gets_its_own_init() -> None:
    class Base(Record):
        a: int

    assert Base(1).a == 1  # Base's __init__ is compiled now

    class Sub(Base):
        b: int = 2

    assert Sub(1, 3).b == 3 and Sub(1) == Sub(a=1, b=2)
    assert Base(5) == Base(a=5)
