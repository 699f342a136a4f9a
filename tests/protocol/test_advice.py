"""Every controller error number has a sentence a student can act on, with its code."""

from __future__ import annotations

import re

import pytest

from melfa.protocol.advice import FIX_LABELS, Fix, advice_for, error_code
from melfa.protocol.error_table import ERROR_MESSAGES

WIRE = re.compile(r"\d;\d;|EXEC|JOG\d|RUN\d|SRVON|RSTALRM|MSVC|Error:|Traceback")


@pytest.mark.parametrize("number", [*sorted(ERROR_MESSAGES), 9999, 1])
def test_every_number_reads_as_what_and_what_to_do(number: int) -> None:
    advice = advice_for(number)
    assert advice.message.endswith(".") and len(advice.message.split(".")) >= 3
    assert not WIRE.search(advice.message), advice.message
    assert advice.code.endswith(f"{number:04d}")
    assert advice.to_json()["code"] == advice.code


def test_the_fixes_the_issue_names() -> None:
    assert (advice_for(2000).fix, advice_for(2000).fix_label) == (
        Fix.SERVO_ON_RETRY,
        "Turn on and retry",
    )
    assert advice_for(4140).fix_label == "Load project"
    assert advice_for(5600).fix is Fix.RESET_ALARM
    assert error_code(2000) == "L2000" and error_code(1630) == "C1630"
    assert set(FIX_LABELS) == set(Fix)
