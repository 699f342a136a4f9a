"""Every answer parser keeps its contract over real replies and their near variants.

The real controller's answers (`tests.fixtures.real_traffic`) are mutated the way a line, a
firmware or a relay varies them: a field dropped, emptied or doubled, a character replaced
(a Unicode digit such as ``²``, ``****``, ``nan``, a separator), the text cut short. Whatever
comes in, a parser returns a value or raises `RemoteProtocolError`; nothing else escapes
(a `ValueError` from ``int("²")`` once ended the robot service's worker).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from melfa.protocol import (
    DState,
    ErrorLogEntry,
    ErrorStatus,
    OpenBanner,
    Parameter,
    Position,
    ProgramEntry,
    RemoteProtocolError,
    State,
)
from tests.fixtures.real_traffic import PAIRS

PARSERS: tuple[Callable[[str], object], ...] = (
    OpenBanner.parse,
    Position.parse,
    State.parse,
    DState.parse,
    ErrorStatus.parse,
    ErrorLogEntry.parse,
    ProgramEntry.parse,
    Parameter.parse,
)

REAL_ANSWERS = sorted({reply[3:] for _tag, _request, reply in PAIRS if reply[:3] in ("QoK", "Qok")})
ODD = ["²", "³", "٣", "½", "****", "*", "", ";", ";;", ",", "nan", "inf", "1e999", "-", " ", "\r\n"]


@st.composite
def variants(draw: st.DrawFn) -> str:
    """A real answer with one to three plausible changes."""
    fields = draw(st.sampled_from(REAL_ANSWERS)).split(";")
    for _ in range(draw(st.integers(1, 3))):
        index = draw(st.integers(0, len(fields) - 1))
        change = draw(st.sampled_from(["drop", "empty", "double", "replace", "insert", "char"]))
        if change == "drop" and len(fields) > 1:
            del fields[index]
        elif change == "empty":
            fields[index] = ""
        elif change == "double":
            fields.insert(index, fields[index])
        elif change == "replace":
            fields[index] = draw(st.sampled_from(ODD))
        elif change == "insert":
            fields.insert(index, draw(st.sampled_from(ODD)))
        elif change == "char" and fields[index]:
            at = draw(st.integers(0, len(fields[index]) - 1))
            text = fields[index]
            fields[index] = text[:at] + draw(st.sampled_from(ODD)) + text[at + 1 :]
    answer = ";".join(fields)
    return answer[: draw(st.integers(0, len(answer)))] if draw(st.booleans()) else answer


@settings(max_examples=400, deadline=None)
@given(variants())
def test_parsers_return_or_raise_only_their_protocol_error(answer: str) -> None:
    for parse in PARSERS:
        with contextlib.suppress(RemoteProtocolError):
            parse(answer)


@pytest.mark.parametrize("answer", REAL_ANSWERS)
def test_every_real_answer_keeps_the_contract_in_every_parser(answer: str) -> None:
    for parse in PARSERS:
        with contextlib.suppress(RemoteProtocolError):
            parse(answer)


def test_a_banner_with_a_superscript_digit_parses_without_a_task_count() -> None:
    banner = OpenBanner.parse(
        "3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-6S;CRn-5xx;MELFA;05-07-14;Ver.K4a;ENG;C;1;1;²;"
    )
    assert banner.robot_type == "RV-6S"
    assert banner.task_max is None


def test_a_position_with_every_axis_unknown_is_a_state_not_an_error() -> None:
    position = Position.parse(
        "J1;****;J2;****;J3;****;J4;****;J5;****;J6;****;;****,****;100;0.00;00000000"
    )
    assert position.unknown and position.fl1 is None and position.override == 100
