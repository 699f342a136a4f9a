"""Serve a `VirtualController` over a pseudo-terminal or TCP (thin I/O around `WireSession`).

- `PtyServer`: the client opens the slave side with pyserial at 9600 8E2, the real serial
  code path. Each connection needs a **fresh** pty: a pty ignores parity, and reopening one
  whose termios already has parity set fails, so `new_port()` hands out a new slave path
  every time (tests get one each; `melfa sim --pty` prints the next after a disconnect).
- `TcpServer` (`tcp://host:port`): one client at a time, like the controller's single port;
  a second client is accepted and closed at once, a clear refusal instead of a hang.

The controller's clock is real time here (`time.monotonic` from when the server started).
Pacing (line speed and controller latency) is applied to replies only; see `Pacing`.
"""

from __future__ import annotations

import contextlib
import errno
import functools
import os
import select
import socket
import threading
import time
import tty
from collections.abc import Callable
from dataclasses import dataclass, field

from melfa.sim.controller import VirtualController
from melfa.sim.session import NO_PACING, Answer, Pacing, WireSession

POLL_S = 0.05
"""How often idle server threads look at their stop flag."""

Clock = Callable[[], float]


class _Base:
    def __init__(
        self,
        controller: VirtualController | None,
        pacing: Pacing,
        clock: Clock,
    ) -> None:
        self.controller = controller if controller is not None else VirtualController()
        self.pacing = pacing
        self._clock = clock
        self._origin = clock()
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._threads: list[threading.Thread] = []

    def now(self) -> float:
        """Controller time: seconds since the server started."""
        return self._clock() - self._origin

    def _send(self, write: Callable[[bytes], None], answer: Answer, received: float) -> None:
        """Write one reply, after the request's wire time and the controller latency, one
        character at a time at line speed."""
        start = received + self.pacing.reply_delay(answer.request_size)
        if self.pacing.seconds_per_char <= 0:
            self._sleep_until(start)
            write(answer.reply)
            return
        for index in range(len(answer.reply)):
            self._sleep_until(start + index * self.pacing.seconds_per_char)
            write(answer.reply[index : index + 1])

    def _sleep_until(self, when: float) -> None:
        delay = when - self._clock()
        if delay > 0:
            self._stop.wait(delay)

    def _spawn(self, target: Callable[[], None], name: str) -> None:
        thread = threading.Thread(target=target, name=name, daemon=True)
        self._threads.append(thread)
        thread.start()

    def close(self) -> None:
        """Stop serving and wait for the server threads (safe to call twice)."""
        self._stop.set()
        for thread in self._threads:
            if thread is not threading.current_thread():
                thread.join(timeout=2)
        self._threads = [t for t in self._threads if t.is_alive()]


@dataclass
class PtyPort:
    """One pseudo-terminal handed out by `PtyServer`."""

    path: str
    master: int
    slave: int | None
    session: WireSession
    connected: bool = False
    closed: threading.Event = field(default_factory=threading.Event)


class PtyServer(_Base):
    """Serve the controller on pseudo-terminals, a fresh one per connection.

    >>> with PtyServer() as server:
    ...     path = server.new_port()
    ...     path.startswith("/dev/")
    True
    """

    def __init__(
        self,
        controller: VirtualController | None = None,
        *,
        pacing: Pacing = NO_PACING,
        clock: Clock = time.monotonic,
    ) -> None:
        super().__init__(controller, pacing, clock)
        self.ports: list[PtyPort] = []

    def __enter__(self) -> PtyServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def new_port(self, controller: VirtualController | None = None) -> str:
        """Open a new pty, serve it in a thread, return the slave path for the client.

        `controller` serves this port only (default: the server's own)."""
        master, slave = os.openpty()
        # Raw mode before anyone opens it: no echo of our replies back to us, no CR→LF.
        tty.setraw(slave)
        path = os.ttyname(slave)
        lock = self._lock if controller is None else threading.Lock()
        session = WireSession(controller or self.controller, lock)
        port = PtyPort(path, master, slave, session)
        self.ports.append(port)
        self._spawn(lambda: self._serve(port), f"melfa-sim-pty {path}")
        return path

    def wait_closed(self, path: str, timeout: float | None = None) -> bool:
        """Block until the client of `path` has disconnected (or the server stops)."""
        for port in self.ports:
            if port.path == path:
                return port.closed.wait(timeout)
        raise KeyError(path)

    def serve_forever(self, on_port: Callable[[str], None]) -> None:
        """Hand out one pty after another: call `on_port(path)`, wait for that client to
        come and go, repeat, until `close()` (or Ctrl-C in the caller's thread)."""
        while not self._stop.is_set():
            path = self.new_port()
            on_port(path)
            while not self._stop.is_set() and not self.wait_closed(path, POLL_S * 4):
                pass

    def _serve(self, port: PtyPort) -> None:
        try:
            while not self._stop.is_set():
                ready, _, _ = select.select([port.master], [], [], POLL_S)
                if not ready:
                    received = self._clock()
                    for answer in port.session.receive_idle(self.now()):
                        self._send(lambda b: _write_all(port.master, b), answer, received)
                    continue
                try:
                    data = os.read(port.master, 4096)
                except OSError as exc:
                    if exc.errno != errno.EIO:
                        raise
                    data = b""
                if not data:
                    if port.connected:
                        break  # the client closed the slave: this pty is used up
                    self._stop.wait(POLL_S)
                    continue
                received = self._clock()
                if not port.connected:
                    port.connected = True
                    # From now on the client's close shows as EIO on the master.
                    self._close_fd(port, "slave")
                for answer in port.session.receive(data, self.now()):
                    self._send(lambda b: _write_all(port.master, b), answer, received)
        except OSError:
            pass  # the client vanished mid-reply; nothing to tell it
        finally:
            port.session.disconnect(self.now())
            self._close_fd(port, "slave")
            self._close_fd(port, "master")
            port.closed.set()

    @staticmethod
    def _close_fd(port: PtyPort, which: str) -> None:
        fd = getattr(port, which)
        if fd is not None:
            with contextlib.suppress(OSError):
                os.close(fd)
            setattr(port, which, None)

    def close(self) -> None:
        super().close()
        for port in self.ports:
            self._close_fd(port, "slave")
            self._close_fd(port, "master")


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        written = os.write(fd, view)
        view = view[written:]


class TcpServer(_Base):
    """Serve the controller on TCP, one client at a time.

    >>> with TcpServer() as server:
    ...     server.url.startswith("tcp://127.0.0.1:")
    True
    """

    def __init__(
        self,
        controller: VirtualController | None = None,
        *,
        host: str = "127.0.0.1",
        port: int = 0,
        pacing: Pacing = NO_PACING,
        clock: Clock = time.monotonic,
    ) -> None:
        super().__init__(controller, pacing, clock)
        self._listener = socket.create_server((host, port))
        self._listener.settimeout(POLL_S)
        self._busy = threading.Event()
        self.refused = 0
        self._spawn(self._accept_loop, "melfa-sim-tcp")

    def __enter__(self) -> TcpServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def address(self) -> tuple[str, int]:
        host, port = self._listener.getsockname()[:2]
        return str(host), int(port)

    @property
    def url(self) -> str:
        host, port = self.address
        return f"tcp://{host}:{port}"

    def wait(self) -> None:
        """Block until `close()` (for the CLI)."""
        while not self._stop.wait(POLL_S * 4):
            pass

    def _accept_loop(self) -> None:
        while not self._stop.is_set():
            try:
                conn, _ = self._listener.accept()
            except TimeoutError:
                continue
            except OSError:
                break
            if self._busy.is_set():
                # The controller's port takes one client; tell the second one at once.
                self.refused += 1
                conn.close()
                continue
            self._busy.set()
            self._spawn(functools.partial(self._serve, conn), "melfa-sim-tcp-client")

    def _serve(self, conn: socket.socket) -> None:
        session = WireSession(self.controller, self._lock)
        conn.settimeout(POLL_S)
        try:
            while not self._stop.is_set():
                try:
                    data = conn.recv(4096)
                except TimeoutError:
                    received = self._clock()
                    for answer in session.receive_idle(self.now()):
                        self._send(conn.sendall, answer, received)
                    continue
                if not data:
                    break
                received = self._clock()
                for answer in session.receive(data, self.now()):
                    self._send(conn.sendall, answer, received)
        except OSError:
            pass
        finally:
            session.disconnect(self.now())
            conn.close()
            self._busy.clear()

    def close(self) -> None:
        super().close()
        with contextlib.suppress(OSError):
            self._listener.close()
