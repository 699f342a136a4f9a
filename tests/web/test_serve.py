"""`melfa serve` for real: a subprocess on a free port, waited for until /api/health
answers (datasette's test_playwright habit), then stopped with Ctrl+C."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import urllib.request
from pathlib import Path
from typing import Any

import pytest

from tests.waiting import wait_until


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.slow
def test_serve_starts_answers_and_stops_cleanly(tmp_path: Path) -> None:
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_ADMIN_PASSWORD")}
    proc = subprocess.Popen(
        [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(tmp_path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:

        def answer() -> Any:
            assert proc.poll() is None, proc.stderr.read() if proc.stderr else "it stopped"
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/health", timeout=2) as r:
                    return json.loads(r.read())
            except OSError:
                return None

        health = wait_until(answer, 30, "melfa serve to answer /api/health")
        assert health["status"] == "ok" and health["robot"]["link"] == "connected"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 130, err  # Ctrl-C: 130, after a clean shutdown
    assert "Traceback" not in err
    assert f"http://127.0.0.1:{port}/" in out and "melfa stopped" in out
    assert "Created the first account: admin with password" in out
    assert '"path": "/api/health"' in err  # structured request log
    assert (tmp_path / "melfa.sqlite3").is_file()
