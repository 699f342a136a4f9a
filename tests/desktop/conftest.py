"""A real `melfa serve` (virtual robot) in a subprocess on a free port, shared by the
desktop tests; Qt fixtures live in the Qt test modules so the pure ones run without it."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

ADMIN_PASSWORD = "desktop-test-pass-1"
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@dataclass(frozen=True)
class Server:
    url: str
    password: str


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="package")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    data = tmp_path_factory.mktemp("desktop-data")
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_DATA")}
    env["MELFA_ADMIN_PASSWORD"] = ADMIN_PASSWORD
    log_path = data / "serve.log"  # a file, not a pipe: a full pipe would block the server
    log = log_path.open("w", encoding="utf-8")
    proc = subprocess.Popen(
        [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)],
        stdout=subprocess.DEVNULL,
        stderr=log,
        text=True,
        env=env,
    )
    url = f"http://127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 60
        healthy = False
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                with urllib.request.urlopen(f"{url}/api/health", timeout=2) as reply:
                    healthy = json.loads(reply.read())["robot"]["link"] == "connected"
                if healthy:
                    break
            except OSError:
                pass
            time.sleep(0.1)
        if not healthy:
            log.flush()
            err = log_path.read_text(encoding="utf-8")
            pytest.fail(f"melfa serve did not come up: {err[-2000:]}")
        yield Server(url, ADMIN_PASSWORD)
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGINT)
            try:
                proc.communicate(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.communicate()
        log.close()
