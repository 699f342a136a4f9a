"""Links around links: a traffic trace (pyserial's ``spy://``) and 9600-baud pacing."""

from __future__ import annotations

import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from melfa.link.base import Link


class _Wrapper(Link):
    def __init__(self, inner: Link, description: str | None = None) -> None:
        super().__init__(inner.settings, description or inner.description)
        self.inner = inner

    def _write(self, data: bytes) -> None:
        self.inner.write(data)

    def _read(self, timeout: float) -> bytes:
        return self.inner._read(timeout)

    def _read_ready(self) -> bytes:
        return self.inner._read_ready()

    def _wake(self) -> None:
        self.inner._wake()

    def _close(self) -> None:
        self.inner.close()


def render(data: bytes) -> str:
    """Bytes as readable text: ``QoK<CR><LF>``, ``<VT>``, other bytes as ``\\xNN``."""
    names = {13: "<CR>", 10: "<LF>", 11: "<VT>", 0: "<NUL>"}
    out = []
    for byte in data:
        if byte in names:
            out.append(names[byte])
        elif 32 <= byte < 127:
            out.append(chr(byte))
        else:
            out.append(f"\\x{byte:02x}")
    return "".join(out)


@dataclass(frozen=True)
class TraceEvent:
    """One line of a trace: seconds since the link opened, ``->`` sent / ``<-`` received,
    and the exact bytes."""

    seconds: float
    direction: str
    data: bytes


def load_trace(lines: Iterable[str]) -> list[TraceEvent]:
    """Read back what `TraceLink` wrote (``--trace FILE``): the hex part is authoritative,
    so the bytes replay exactly. Lines that are not trace lines are skipped."""
    events = []
    for line in lines:
        parts = line.split(None, 2)
        if len(parts) < 3 or parts[1] not in ("->", "<-") or not line.rstrip().endswith("]"):
            continue
        hex_part = line.rstrip()[line.rindex("[") + 1 : -1]
        try:
            events.append(TraceEvent(float(parts[0]), parts[1], bytes.fromhex(hex_part)))
        except ValueError:
            continue
    return events


class TraceLink(_Wrapper):
    """Logs both directions as text and hex: ``  0.125 -> 1;1;JPOSF<CR>  [31 3b 31 …]``
    (`load_trace` reads it back). One line per request and one per reply: a serial port
    hands a reply over a few bytes at a time, so received bytes are held until their
    ``<CR>`` (stamped then); a reply cut short shows as it is before the next request or
    when the link closes."""

    def __init__(self, inner: Link, sink: Callable[[str], None] | None = None) -> None:
        super().__init__(inner)
        self._sink = sink or (lambda line: print(line, file=sys.stderr, flush=True))
        self._start = time.monotonic()
        self._partial = b""
        self._trace_lock = threading.Lock()

    def _log(self, arrow: str, data: bytes) -> None:
        stamp = time.monotonic() - self._start
        self._sink(f"{stamp:8.3f} {arrow} {render(data)}  [{data.hex(' ')}]")

    def _received(self, data: bytes) -> None:
        with self._trace_lock:
            self._partial += data
            while b"\r" in self._partial:
                reply, _, self._partial = self._partial.partition(b"\r")
                self._log("<-", reply + b"\r")

    def _flush_partial(self) -> None:
        with self._trace_lock:
            if self._partial:
                self._log("<-", self._partial)
                self._partial = b""

    def _write(self, data: bytes) -> None:
        self._flush_partial()
        self._log("->", data)
        super()._write(data)

    def _read(self, timeout: float) -> bytes:
        data = super()._read(timeout)
        if data:
            self._received(data)
        return data

    def _read_ready(self) -> bytes:
        data = super()._read_ready()
        if data:
            self._received(data)
        return data

    def _close(self) -> None:
        self._flush_partial()
        super()._close()


class PacedLink(_Wrapper):
    """Delays bytes like a real line: ``bits_per_char / baudrate`` per character each way
    (12 bits at 8E2: 1.25 ms a character at 9600 baud [DERIVED protocol.md §6.1]).

    Writes return when the last character would have left the wire; received bytes are handed
    over when the last of them would have arrived. The two directions are independent
    (RS-232 is full duplex). ``latency`` adds the controller's processing time between the
    end of a request and the start of its reply (measured 0.1–0.15 s, prior-art.md §5).
    For benchmarks over an in-memory controller; ``now`` and ``sleep`` let a test run the
    line on its own clock.
    """

    def __init__(
        self,
        inner: Link,
        latency: float = 0.0,
        *,
        now: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        super().__init__(inner, f"{inner.description}, paced")
        self.char_time = inner.settings.seconds_per_char
        self.latency = latency
        self._now = now
        self._sleep = sleep
        self._tx_free = 0.0
        self._rx_free = 0.0
        self._request_ends: deque[float] = deque()
        self._pace_lock = threading.Lock()

    def _write(self, data: bytes) -> None:
        with self._pace_lock:
            self._tx_free = max(self._now(), self._tx_free) + len(data) * self.char_time
            until = self._tx_free
            self._request_ends.extend([until] * max(1, data.count(b"\r")))
        self._sleep_until(until)
        super()._write(data)

    def _read(self, timeout: float) -> bytes:
        data = super()._read(timeout)
        if data:
            with self._pace_lock:
                # Each reply starts after the end of *its* request plus the latency.
                pieces = data.split(b"\r")
                for index, piece in enumerate(pieces):
                    ends_reply = index < len(pieces) - 1
                    if not piece and not ends_reply:
                        break
                    asked = self._request_ends[0] if self._request_ends else 0.0
                    start = max(self._now(), self._rx_free, asked + self.latency)
                    self._rx_free = start + (len(piece) + ends_reply) * self.char_time
                    if ends_reply and self._request_ends:
                        self._request_ends.popleft()
                until = self._rx_free
            self._sleep_until(until)
        return data

    def _sleep_until(self, when: float) -> None:
        while (left := when - self._now()) > 0:
            self._sleep(left)


__all__ = ["PacedLink", "TraceEvent", "TraceLink", "load_trace", "render"]
