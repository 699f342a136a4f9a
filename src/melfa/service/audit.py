"""Audit sinks: where "who moved the arm, when, with what result" is kept.

The service writes two `AuditEvent`s per command (accepted, then the outcome), and a
`RobotNote` for what no command asked for (control changing hands, alarms, the link). The store
engineer provides a SQLite-backed sink with the same one-method protocol; `write` is called
on the event loop's thread, so a sink must be quick (buffer, or hand off to its own writer).
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from melfa.service.events import AuditEvent, RobotNote


@runtime_checkable
class AuditSink(Protocol):
    def write(self, entry: AuditEvent) -> None:
        """Keep ``entry``; must not block for long and should not raise."""

    def note(self, entry: RobotNote) -> None:
        """Keep ``entry`` (the same rules as `write`)."""


class MemoryAuditSink:
    """Keeps entries in a list (tests, the embedded default).

    >>> sink = MemoryAuditSink()
    >>> from melfa.vocab.commands import Command
    >>> sink.write(AuditEvent(command_id=1, command=Command.RUN))
    >>> [e.result for e in sink.entries]
    ['accepted']
    """

    def __init__(self, limit: int = 10000) -> None:
        self.limit = limit
        self.entries: list[AuditEvent] = []
        self.notes: list[RobotNote] = []

    def write(self, entry: AuditEvent) -> None:
        self.entries.append(entry)
        if len(self.entries) > self.limit:
            del self.entries[: len(self.entries) - self.limit]

    def note(self, entry: RobotNote) -> None:
        self.notes.append(entry)
        if len(self.notes) > self.limit:
            del self.notes[: len(self.notes) - self.limit]


__all__ = ["AuditSink", "MemoryAuditSink"]
