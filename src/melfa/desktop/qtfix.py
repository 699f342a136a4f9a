"""A guard against a reference-counting bug of PySide6 6.12 on Python 3.11.

Measured here (PySide6-Essentials 6.12.0, CPython 3.11): every call of a Qt method that
returns nothing (``QLabel.setText``, ``QStatusBar.showMessage``...) drops one reference to
`None`, and every Python-side ``Signal.emit()`` drops one to `True`. On Python 3.12+ these
objects are immortal and nothing happens; on 3.11 their count reaches zero after a few
thousand calls and the interpreter aborts ("deallocating None"). A live window updating
twenty times a second gets there in seconds.

The singletons are never freed anyway, so giving them a large reserve of references is
harmless; `top_up` does that whenever the reserve runs low, and `application()` calls it
from a timer. Remove this module when the project requires Python 3.12 or a fixed PySide6.
"""

from __future__ import annotations

import ctypes
import sys

NEEDED = sys.version_info < (3, 12)
"""Python 3.12+ has immortal None/True/False (PEP 683): nothing to guard."""
FLOOR = 1 << 20
"""Top up when a singleton has fewer references than this (about a million)."""
RESERVE = 1 << 24
"""References added per top-up: hours of a busy window between top-ups."""
INTERVAL_MS = 1000
SINGLETONS: tuple[object, ...] = (None, True, False)


def top_up() -> int:
    """Add `RESERVE` references to each singleton below `FLOOR`; how many were topped up.

    >>> before = sys.getrefcount(None)
    >>> n = top_up()
    >>> sys.getrefcount(None) >= min(before, FLOOR)
    True
    """
    if not NEEDED:
        return 0
    count = 0
    for obj in SINGLETONS:
        if sys.getrefcount(obj) < FLOOR:
            # CPython ≤ 3.11: ob_refcnt is the object's first field, at id(obj).
            ctypes.c_ssize_t.from_address(id(obj)).value += RESERVE
            count += 1
    return count


__all__ = ["FLOOR", "INTERVAL_MS", "NEEDED", "RESERVE", "top_up"]
