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
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from tests.waiting import wait_until


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _serve(port: int, data: Path, before: Callable[[], None] | None = None) -> Any:
    """`melfa serve` on ``port`` with ``data``, its output in pipes (``before``: run in the
    child before it starts, as its parent would set it up)."""
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_ADMIN_PASSWORD")}
    return subprocess.Popen(
        [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        preexec_fn=before,
    )


@pytest.mark.slow
def test_serve_starts_answers_and_stops_cleanly(tmp_path: Path) -> None:
    port = free_port()
    proc = _serve(port, tmp_path)
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
    assert "Traceback" not in err and "Exception ignored" not in err, err
    assert f"http://127.0.0.1:{port}/" in out and "melfa stopped" in out
    assert "Created the first account: admin with password" in out
    assert '"path": "/api/health"' in err  # structured request log
    assert (tmp_path / "melfa.sqlite3").is_file()


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("how", "sent", "status"),
    [
        # A script's `&` starts it with SIGINT ignored; `kill -INT` (or Ctrl-C reaching it)
        # still stops it, as uvicorn takes the signal while serving: 130 all the same.
        ("started by a script's &", signal.SIGINT, 130),
        # A service manager's stop (systemd's default, docker stop, supervisord): 0.
        ("stopped by a service manager", signal.SIGTERM, 0),
    ],
)
def test_serve_says_how_it_was_stopped_after_a_clean_shutdown(
    tmp_path: Path, how: str, sent: signal.Signals, status: int
) -> None:
    port = free_port()
    proc = _serve(port, tmp_path, _ignore_sigint if sent is signal.SIGINT else None)
    try:

        def answers() -> bool:
            assert proc.poll() is None, proc.stderr.read() if proc.stderr else "it stopped"
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/health", timeout=2):
                    return True
            except OSError:
                return False

        wait_until(answers, 30, "melfa serve to answer /api/health")
        proc.send_signal(sent)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == status, (how, err)
    assert "melfa stopped" in out, how
    # Its store was closed (the write-ahead log folded in), and nothing complained on the
    # way out (SIGTERM's default handler used to kill it first: 'leaked semaphore objects').
    assert not (tmp_path / "melfa.sqlite3-wal").exists(), how
    # (Nor did Python's exit handler race the check workers' pool: "Exception ignored".)
    assert "Traceback" not in err and "leaked" not in err, err
    assert "Exception ignored" not in err, err
