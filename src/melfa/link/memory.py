"""An in-process link: each request line goes to a function that returns the reply bytes.

This is how ``--robot sim`` runs without a port: the virtual controller's ``handle`` is the
function. The responder runs in the writer's thread, synchronously, like a controller that
answers instantly; wrap the link in `PacedLink` to get 9600-baud wire timing back.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from melfa.link.base import Link
from melfa.link.errors import LinkClosed
from melfa.link.settings import LinkSettings
from melfa.protocol import LineSplitter

Responder = Callable[[bytes], bytes]
"""One request line (no terminator) -> the reply bytes, terminator included (b"" = silence)."""


class MemoryLink(Link):
    """Requests to a `Responder`, replies back through a buffer."""

    def __init__(
        self,
        respond: Responder,
        settings: LinkSettings | None = None,
        description: str = "in-memory controller",
        on_close: Callable[[], None] | None = None,
    ) -> None:
        super().__init__(settings or LinkSettings(), description)
        self._respond = respond
        self._on_close = on_close
        self._lines = LineSplitter(max_size=4096)
        self._rx = bytearray()
        self._ready = threading.Condition()
        self._hung_up = False

    def _write(self, data: bytes) -> None:
        if self._hung_up:
            raise LinkClosed(f"{self.description} hung up")
        self._lines.feed(data.replace(b"\x00", b"\r"))
        while (line := self._lines.next_line()) is not None:
            if not line:
                continue
            reply = self._respond(line)
            with self._ready:
                self._rx += reply
                self._ready.notify_all()

    def _read(self, timeout: float) -> bytes:
        with self._ready:
            if not self._rx:
                if self._hung_up:
                    raise LinkClosed(f"{self.description} hung up")
                self._ready.wait(timeout)
            data = bytes(self._rx)
            self._rx.clear()
            return data

    def hang_up(self) -> None:
        """Simulate the peer going away (tests): reads and writes then raise `LinkClosed`."""
        with self._ready:
            self._hung_up = True
            self._ready.notify_all()

    def _wake(self) -> None:
        with self._ready:
            self._ready.notify_all()

    def _close(self) -> None:
        if self._on_close is not None:
            self._on_close()
