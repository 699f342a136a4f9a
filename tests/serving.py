"""A real `melfa serve` for the tests that need one: a subprocess on a free port with its
own data folder, awaited until its robot link is up, stopped with SIGINT. The one start-up
of a served melfa, shared by the browser and the desktop tests."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import urllib.request
from collections.abc import Iterator
from pathlib import Path

from tests.waiting import wait_until


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def stop_process(proc: subprocess.Popen[bytes]) -> None:
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=15)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


@contextlib.contextmanager
def melfa_serve(
    data: Path, *extra: str, admin_password: str, timeout: float = 120.0
) -> Iterator[str]:
    """`melfa serve` on a free port with ``data`` and ``extra`` options, its output in
    data/serve.log (a file, not a pipe: a full pipe would block the server); yields its URL
    once /api/health says the robot link is connected (``timeout`` s: a guard against a hang;
    a start-up on two cores under a second suite took over 30 s), and stops it at the end."""
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_DATA")}
    env["MELFA_ADMIN_PASSWORD"] = admin_password
    log_path = data / "serve.log"
    command = [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)]
    url = f"http://127.0.0.1:{port}"
    with log_path.open("w") as log:
        proc = subprocess.Popen([*command, *extra], stdout=log, stderr=subprocess.STDOUT, env=env)

        def connected() -> bool:
            assert proc.poll() is None, log_path.read_text()
            try:
                with urllib.request.urlopen(url + "/api/health", timeout=2) as reply:
                    return bool(json.loads(reply.read())["robot"]["link"] == "connected")
            except OSError:
                return False

        try:
            wait_until(connected, timeout, what=lambda: f"melfa serve: {log_path.read_text()}")
            yield url
        finally:
            stop_process(proc)
