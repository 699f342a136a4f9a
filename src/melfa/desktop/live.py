"""The WebSocket side of the API (`/api/ws`) in a background thread. No Qt.

`LiveFeed` keeps one socket open (the browser's one-per-tab), authenticated by the session
cookie, parses each message (`melfa.desktop.messages`) and hands it to a callback on its
own thread; the presenter forwards it to the GUI thread. A dropped socket is reopened
after a short wait; a refusal (not signed in, 1008 / HTTP 403) ends the feed. Closing the
feed closes the socket, which is also the server's dead-man: a jog started by this
client stops, and its lease ends with its last socket.
"""

from __future__ import annotations

import enum
import json
import threading
from collections.abc import Callable, Mapping

from websockets.exceptions import ConnectionClosed, InvalidStatus, WebSocketException
from websockets.sync.client import ClientConnection, connect

from melfa.desktop.messages import LiveMessage, parse_message

POLICY_VIOLATION = 1008
"""The server's close code for a socket it will not serve (docs/api.md)."""
RETRY_DELAYS_S = (0.5, 1.0, 2.0, 5.0)
"""Waits before reopening a dropped socket; the last one repeats."""


class FeedStatus(enum.Enum):
    CONNECTING = "connecting"
    CONNECTED = "connected"
    DISCONNECTED = "disconnected"
    REFUSED = "refused"
    CLOSED = "closed"


MessageHandler = Callable[[LiveMessage], None]
StatusHandler = Callable[[FeedStatus, str], None]


class LiveFeed:
    """One WebSocket, reopened when it drops, until `close()`."""

    def __init__(
        self,
        url: str,
        headers: Mapping[str, str],
        on_message: MessageHandler,
        on_status: StatusHandler,
    ) -> None:
        self.url = url
        self.headers = dict(headers)
        self._on_message = on_message
        self._on_status = on_status
        self._closing = threading.Event()
        self._lock = threading.Lock()
        self._socket: ClientConnection | None = None
        self._thread = threading.Thread(target=self._run, name="melfa-desktop-ws", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def close(self, timeout: float = 5.0) -> None:
        """Close the socket and wait for the thread (bounded)."""
        self._closing.set()
        with self._lock:
            sock = self._socket
        if sock is not None:
            sock.close()
        if self._thread.is_alive():
            self._thread.join(timeout)

    def send(self, message: Mapping[str, object]) -> bool:
        """Send one JSON message from any thread (the sync client allows a send beside the
        reading thread); False when no socket is open or it just closed."""
        with self._lock:
            sock = self._socket
        if sock is None:
            return False
        try:
            sock.send(json.dumps(message))
        except (ConnectionClosed, OSError, RuntimeError):
            return False
        return True

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    def _run(self) -> None:
        attempt = 0
        while not self._closing.is_set():
            self._on_status(FeedStatus.CONNECTING, self.url)
            reason = ""
            try:
                # proxy=None: the lab server is on the LAN, not behind the internet proxy.
                with connect(
                    self.url, additional_headers=self.headers, proxy=None, open_timeout=5
                ) as sock:
                    with self._lock:
                        self._socket = sock
                    if self._closing.is_set():
                        break
                    attempt = 0
                    self._on_status(FeedStatus.CONNECTED, self.url)
                    for raw in sock:
                        self._dispatch(raw)
            except InvalidStatus as exc:
                status = exc.response.status_code
                self._on_status(
                    FeedStatus.REFUSED, f"the server refused the socket (HTTP {status})"
                )
                return
            except ConnectionClosed as exc:
                code = exc.rcvd.code if exc.rcvd is not None else None
                if code == POLICY_VIOLATION:
                    text = exc.rcvd.reason if exc.rcvd is not None else ""
                    self._on_status(FeedStatus.REFUSED, text or "the server refused the socket")
                    return
                reason = "connection dropped"
            except (OSError, WebSocketException, TimeoutError) as exc:
                reason = str(exc) or type(exc).__name__
            finally:
                with self._lock:
                    self._socket = None
            if self._closing.is_set():
                break
            self._on_status(FeedStatus.DISCONNECTED, reason or "the server closed the socket")
            delay = RETRY_DELAYS_S[min(attempt, len(RETRY_DELAYS_S) - 1)]
            attempt += 1
            self._closing.wait(delay)
        self._on_status(FeedStatus.CLOSED, "")

    def _dispatch(self, raw: str | bytes) -> None:
        try:
            data = json.loads(raw)
        except ValueError:
            return  # a garbled message is the server's fault; skip it, keep the feed
        message = parse_message(data)
        if message is not None:
            self._on_message(message)


__all__ = ["RETRY_DELAYS_S", "FeedStatus", "LiveFeed", "MessageHandler", "StatusHandler"]
