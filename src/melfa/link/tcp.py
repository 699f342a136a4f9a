"""``tcp://host:port``: Ethernet controllers (and ``melfa sim --tcp``) speak the same protocol.

Note: real Ethernet controllers may be set to no terminator (S11) or NUL (S12); choose it with
`LinkSettings.terminator`.
"""

from __future__ import annotations

import contextlib
import os
import select
import socket
from urllib.parse import urlsplit

from melfa.link.base import Link
from melfa.link.errors import BUSY_HINT, LinkBusy, LinkClosed, LinkError
from melfa.link.settings import LinkSettings


def parse_tcp_url(url: str) -> tuple[str, int]:
    """``tcp://host:port`` -> (host, port); `LinkError` with the expected form otherwise."""
    parts = urlsplit(url)
    try:
        port = parts.port
    except ValueError:
        port = None
    if parts.scheme != "tcp" or not parts.hostname or port is None:
        raise LinkError(f"{url!r} is not of the form tcp://host:port")
    return parts.hostname, port


class TcpLink(Link):
    """A TCP stream; a blocked read wakes through a self-pipe."""

    def __init__(self, url: str, settings: LinkSettings | None = None) -> None:
        settings = settings or LinkSettings()
        super().__init__(settings, url)
        host, port = parse_tcp_url(url)
        try:
            self.sock = socket.create_connection((host, port), timeout=settings.timeout)
        except OSError as exc:
            raise LinkError(f"cannot connect to {host}:{port}: {exc.strerror or exc}") from None
        self.sock.setblocking(True)
        self.sock.settimeout(None)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self._wake_r, self._wake_w = os.pipe()
        self._received = False

    def _write(self, data: bytes) -> None:
        try:
            self.sock.sendall(data)
        except OSError as exc:
            raise self._lost(exc) from None

    def _lost(self, exc: OSError | ValueError) -> LinkError:
        """A failed socket call: a reset or broken pipe before a single reply is the port
        refusing a second client (the close raced our request), like a close at once."""
        if not self._received and isinstance(exc, (ConnectionResetError, BrokenPipeError)):
            return LinkBusy(f"{self.description} closed the connection at once: {BUSY_HINT}")
        return LinkClosed(f"{self.description}: connection lost ({exc})")

    def _read(self, timeout: float) -> bytes:
        try:
            ready, _, _ = select.select([self.sock.fileno(), self._wake_r], [], [], timeout)
            if self._wake_r in ready:
                os.read(self._wake_r, 64)
            if self.sock.fileno() not in ready:
                return b""
            data = self.sock.recv(4096)
        except (OSError, ValueError) as exc:
            raise self._lost(exc) from None
        if not data:
            if not self._received:
                # Closed before a single reply: the port serves one client at a time.
                raise LinkBusy(f"{self.description} closed the connection at once: {BUSY_HINT}")
            raise LinkClosed(f"{self.description}: the controller closed the connection")
        self._received = True
        return data

    def _wake(self) -> None:
        with contextlib.suppress(OSError):
            os.write(self._wake_w, b"x")

    def _close(self) -> None:
        try:
            self.sock.close()
        finally:
            os.close(self._wake_r)
            os.close(self._wake_w)
