"""Hold-to-move jog over the live WebSocket: the arm moves only while a key is held.

`jog_start` when a key (or a jog button) goes down, a `jog_heartbeat` every 80 ms while it
stays down, `jog_release` the moment it comes up, the window loses focus or the frame
changes. The heartbeat runs on the GUI thread's timer, so a client that freezes stops
sending it and the server stops the arm ~0.3 s later (docs/api.md, WebSocket "Client →
server"); the controller's own watchdog is behind that. One key moves at a time: pressing
another releases the first. Nothing is queued: a release always goes out at once.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Mapping
from dataclasses import dataclass

from PySide6.QtCore import QTimer

HEARTBEAT_MS = 80
"""Below the server's 100 ms bound, with room for a busy GUI thread."""

Send = Callable[[Mapping[str, object]], bool]


@dataclass(frozen=True)
class JogKey:
    frame: str
    axis: int
    direction: int


class JogHold:
    """The held jog key, its heartbeat and the ids of its `jog_start` requests."""

    def __init__(self, send: Send) -> None:
        self._send = send
        self._ids = itertools.count(1)
        self.held: JogKey | None = None
        self.start_id: int | None = None
        self._timer = QTimer()
        self._timer.setInterval(HEARTBEAT_MS)
        self._timer.timeout.connect(self._beat)

    @property
    def active(self) -> bool:
        return self.held is not None

    def press(self, key: JogKey) -> bool:
        """Start moving along ``key``; False when the socket is not open (nothing moves)."""
        if self.held == key:
            return True  # the keyboard's auto-repeat: the heartbeat keeps it alive
        self.release()
        request_id = next(self._ids)
        message = {
            "type": "jog_start",
            "id": request_id,
            "frame": key.frame,
            "axis": key.axis,
            "direction": key.direction,
            "servo_on": True,  # holding a jog key is asking to move (audited by the server)
        }
        if not self._send(message):
            return False
        self.held, self.start_id = key, request_id
        self._timer.start()
        return True

    def release(self) -> bool:
        """Stop now (key up, focus lost); True when a jog was held."""
        if self.held is None:
            return False
        self.ended()
        self._send({"type": "jog_release"})
        return True

    def ended(self) -> None:
        """The server ended the jog (refused, STOP, heartbeat lost): stop the heartbeat."""
        self.held = None
        self.start_id = None
        self._timer.stop()

    def _beat(self) -> None:
        if self.held is None or not self._send({"type": "jog_heartbeat"}):
            self.ended()


__all__ = ["HEARTBEAT_MS", "JogHold", "JogKey"]
