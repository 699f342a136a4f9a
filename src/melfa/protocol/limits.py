"""The controller's ranges, in one place: hand numbers and the speed override.

Every part checks against these (client, virtual controller, interpreter, service, web
models, CLI) and the browser gets them from the generated ``/model/controller.js``; a test
(`tests/architecture/test_one_home.py`) fails when a second copy of a bound appears.

>>> 8 in HANDS, 9 in HANDS, span_text(HANDS), span_text(OVERRIDE_PERCENT)
(True, False, '1–8', '1–100')
>>> 0.5 in OVERRIDE_PERCENT, is_program_override(0.5), is_program_override(0)
(False, True, False)
"""

from __future__ import annotations

from typing import Final

HANDS: Final = range(1, 9)
"""Hand numbers 1–8: ``HOPEN``/``HCLOSE`` in a program, ``EXECHOPEN n`` and the HNDSTS
answer [DOC S1 HOPEN/HCLOSE]."""

OVERRIDE_PERCENT: Final = range(1, 101)
"""The operation panel's speed override, ``OVRD=`` 1–100 % [DOC S1 §5.2 OVRD]. A program's
``OVRD``/``JOVRD`` also ends at 100 (above 0: fractions run) [DOC S1 OVRD, JOVRD]."""


PROGRAM_OVERRIDE_TEXT: Final = f"above 0 and at most {OVERRIDE_PERCENT[-1]} %"
"""What a program's ``OVRD``/``JOVRD`` takes, in words."""


def is_program_override(percent: float) -> bool:
    """A program's ``OVRD``/``JOVRD``: any value above 0 up to 100 runs (0.5: resolution
    0.1 %); "if 0 or a value over 100 is set, an error will occur" [DOC S1 OVRD, JOVRD]."""
    return 0 < percent <= OVERRIDE_PERCENT[-1]


def span_text(numbers: range) -> str:
    """``1–8``: a range as people write it (both ends included)."""
    return f"{numbers.start}–{numbers.stop - 1}"


__all__ = [
    "HANDS",
    "OVERRIDE_PERCENT",
    "PROGRAM_OVERRIDE_TEXT",
    "is_program_override",
    "span_text",
]
