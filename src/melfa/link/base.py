"""The one narrow surface every transport offers (pyserial's `SerialBase`, shrunk).

A `Link` writes bytes, reads bytes until a deadline, can be woken or closed from another
thread, and cuts replies with `melfa.protocol` (framing is not the transport's job, so the
transports only implement `_write`, `_read`, `_wake` and `_close`).

Deadlines, not per-byte timeouts: `read_reply` fixes one monotonic deadline for the whole
reply, and every partial read shares it. Each low-level wait is at most `POLL_S`, so a close or
cancel from another thread is noticed within that time even on transports that cannot be
woken directly.
"""

from __future__ import annotations

import threading
import time
from abc import ABC, abstractmethod
from types import TracebackType
from typing import Final

from melfa.link.errors import LinkCancelled, LinkClosed, LinkTimeout
from melfa.link.settings import LinkSettings
from melfa.protocol import CR, Reply, ReplyReader, Request

POLL_S: Final = 0.05
"""Longest single wait inside a read; bounds how late a close/cancel is noticed."""


class Link(ABC):
    """A byte link to one controller. Thread-safe for: one reader, one writer at a time,
    `cancel_read` and `close` from any thread."""

    def __init__(self, settings: LinkSettings, description: str) -> None:
        self.settings = settings
        self.description = description
        self._reader = ReplyReader()
        self._closed = False
        self._cancel = threading.Event()
        self._read_lock = threading.Lock()
        self._write_lock = threading.Lock()
        self._state_lock = threading.Lock()

    # ---------------------------------------------------------------- transport hooks

    @abstractmethod
    def _write(self, data: bytes) -> None:
        """Send all of ``data``."""

    @abstractmethod
    def _read(self, timeout: float) -> bytes:
        """Wait at most ``timeout`` s; return what arrived (possibly b"")."""

    def _read_ready(self) -> bytes:
        """What has already arrived, without waiting (transports may do better)."""
        return self._read(0.0)

    def _wake(self) -> None:  # noqa: B027 - optional hook
        """Interrupt a blocked `_read` if the transport can."""

    @abstractmethod
    def _close(self) -> None:
        """Release the transport."""

    # ---------------------------------------------------------------------- public API

    @property
    def closed(self) -> bool:
        """True once `close` was called or the peer hung up."""
        return self._closed

    def write(self, data: bytes) -> None:
        """Send raw bytes."""
        with self._write_lock:
            if self._closed:
                raise LinkClosed(f"{self.description} is closed")
            self._write(data)

    def send(self, request: Request) -> None:
        """Send one request with the configured terminator (CR by default)."""
        data = request.to_bytes()
        if self.settings.terminator != CR:
            data = data[: -len(CR)] + self.settings.terminator
        self.write(data)

    def read_some(self, deadline: float) -> bytes:
        """At least one byte, or `LinkTimeout` at ``deadline`` (a `time.monotonic` value),
        `LinkCancelled` if `cancel_read` was called, `LinkClosed` once closed."""
        with self._read_lock:
            while True:
                if self._closed:
                    raise LinkClosed(f"{self.description} is closed")
                if self._cancel.is_set():
                    self._cancel.clear()
                    raise LinkCancelled(f"read on {self.description} cancelled")
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise LinkTimeout(f"no reply from {self.description} in time")
                data = self._read(min(remaining, POLL_S))
                if data:
                    return data

    def read_now(self) -> bytes:
        """Bytes that have already arrived, without waiting (b"" when none): how the robot
        client checks that a quiet line is really quiet before a request."""
        with self._read_lock:
            if self._closed:
                raise LinkClosed(f"{self.description} is closed")
            return self._read_ready()

    def read_reply(self, timeout: float | None = None) -> Reply:
        """The next reply, under one deadline (``timeout`` or the settings' timeout).

        Garbled input raises `melfa.protocol.RemoteProtocolError`; a reply cut short by the
        deadline raises `LinkTimeout` and the partial bytes are dropped.
        """
        deadline = time.monotonic() + (self.settings.timeout if timeout is None else timeout)
        while True:
            reply = self._reader.next_reply()
            if reply is not None:
                return reply
            try:
                data = self.read_some(deadline)
            except LinkTimeout:
                if self._reader.pending:
                    held = self._reader.pending
                    self._reader.clear()
                    raise LinkTimeout(
                        f"reply from {self.description} incomplete after "
                        f"{held} bytes (no CR before the deadline)"
                    ) from None
                raise
            self._reader.feed(data)

    def exchange(self, request: Request, timeout: float | None = None) -> Reply:
        """Send one request and read its reply (no other request may be in flight)."""
        self.send(request)
        return self.read_reply(timeout)

    def drain(self, quiet: float = 0.2, limit: float = 2.0) -> bytes:
        """Discard input until the line has been quiet for ``quiet`` s (resynchronise)."""
        self._reader.clear()
        dropped = bytearray()
        end = time.monotonic() + limit
        while time.monotonic() < end:
            try:
                dropped += self.read_some(min(end, time.monotonic() + quiet))
            except LinkTimeout:
                break
        return bytes(dropped)

    def cancel_read(self) -> None:
        """Wake a read blocked in another thread with `LinkCancelled`. No effect when idle."""
        if self._read_lock.locked():
            self._cancel.set()
            self._wake()

    def close(self) -> None:
        """Close; safe to call twice and from any thread (waits ≤ `POLL_S` for a reader)."""
        with self._state_lock:
            if self._closed:
                return
            self._closed = True
        self._wake()
        with self._read_lock, self._write_lock:
            self._close()

    def __enter__(self) -> Link:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self._closed else "open"
        return f"<{type(self).__name__} {self.description} {state}>"
