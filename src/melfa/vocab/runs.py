"""How a recorded run on a shared robot ended: one code per end, with the student's words.

The run routes send the code (``outcome``); the IDE shows the words from ``/vocab.js``
(``RUN_OUTCOMES``).

>>> RunOutcome.FINISHED.words
'finished'
>>> RunOutcome.LINK_LOST.words
'the link to the robot was lost'
"""

from __future__ import annotations

import enum


class RunOutcome(enum.StrEnum):
    """Why a recording ended (stable wire value)."""

    FINISHED = "finished"
    """The program reached its end (the controller stopped showing it running)."""
    STOPPED = "stopped"
    """Someone stopped it (STOP), or it was started again."""
    ALARM = "alarm"
    """It ended with an alarm."""
    LINK_LOST = "link-lost"
    """The link to the controller went down mid-run."""
    SERVICE_CLOSED = "service-closed"
    """The server shut down mid-run."""
    TOO_LONG = "too-long"
    """It ran longer than a recording keeps (the rest was not recorded)."""

    @property
    def words(self) -> str:
        return _WORDS[self]


_WORDS: dict[RunOutcome, str] = {
    RunOutcome.FINISHED: "finished",
    RunOutcome.STOPPED: "stopped before the end",
    RunOutcome.ALARM: "ended with an alarm",
    RunOutcome.LINK_LOST: "the link to the robot was lost",
    RunOutcome.SERVICE_CLOSED: "the server shut down during the run",
    RunOutcome.TOO_LONG: "ran too long: only the start was recorded",
}

__all__ = ["RunOutcome"]
