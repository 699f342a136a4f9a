"""A misbehaving controller on a real pty, for garbage, truncation, delays and hang-ups."""

from __future__ import annotations

import contextlib
import os
import select
import threading
import tty
from collections.abc import Callable

Script = Callable[[bytes], "bytes | None"]
"""One request line (no CR) -> bytes to write back (None = hang up)."""


class FakeController:
    def __init__(self, script: Script) -> None:
        self.script = script
        self.master, self._slave = os.openpty()
        tty.setraw(self._slave)
        self.path = os.ttyname(self._slave)
        self.lines: list[bytes] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        buffer = b""
        try:
            while not self._stop.is_set():
                ready, _, _ = select.select([self.master], [], [], 0.02)
                if not ready:
                    continue
                buffer += os.read(self.master, 1024)
                while b"\r" in buffer:
                    line, buffer = buffer.split(b"\r", 1)
                    self.lines.append(line)
                    answer = self.script(line)
                    if answer is None:
                        self.hang_up()
                        return
                    os.write(self.master, answer)
        except OSError:
            pass

    def hang_up(self) -> None:
        for fd in (self._slave, self.master):
            with contextlib.suppress(OSError):
                os.close(fd)

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        self.hang_up()


OPEN_BANNER = (
    b"QoK3F;3F;7,0;3,5,A,1E,32,46,64;MB4;PRM;RV-6S;CRn-5xx;MELFA;09-08-08;Ver.K9b;ENG;FAKE;1;1;8;\r"
)
