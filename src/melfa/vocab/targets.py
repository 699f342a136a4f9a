"""Which robot a user drives, in words: the lab's robot or their own simulator.

Pure: the server names each target with `TARGET_LABELS` (`melfa.web.targets`, the socket's
``hello``), the IDE's header switch reads them and `TARGET_WORDS` from ``/vocab.js``, the
desktop client imports them; keyed by the target's id in ``?target=`` (``lab``, ``mine``).
"""

from __future__ import annotations

__all__ = ["TARGET_LABELS", "TARGET_WORDS"]

TARGET_LABELS: dict[str, str] = {
    "lab": "Lab RV-6S",
    "mine": "My simulator",
}
"""Each target's name, as the header's switch and the 3D view's heading show it."""

TARGET_WORDS: dict[str, str] = {
    "driving": "Driving",
    "page-title": "melfa · {robot}",
    "other-robot": "The live view shows another robot",
    "other-robot-detail": "expected {expected}, got {got}",
}
"""The switch's caption, the page's title (``{robot}``: a `TARGET_LABELS` name) and what the
IDE says when the socket follows another robot than the one chosen."""
