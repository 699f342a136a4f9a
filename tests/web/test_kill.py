"""A `melfa serve` killed with SIGKILL (it cannot shut anything down) leaves no process
behind: its worker processes notice their parent is gone and exit."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

from tests.serving import free_port
from tests.waiting import wait_until


def children(pid: int) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                found.append(int(entry.name))
    return found


def running(pid: int) -> bool:
    """Alive and not a zombie waiting for a parent to reap it."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.slow
def test_worker_processes_exit_when_the_server_is_killed(tmp_path: Path) -> None:
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_DATA")}
    env["MELFA_ADMIN_PASSWORD"] = "kill-nine-lantern-4"
    command = [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(tmp_path)]
    with (tmp_path / "serve.log").open("w") as log:
        proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env)
    try:

        def up() -> bool:
            assert proc.poll() is None, (tmp_path / "serve.log").read_text()
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/health", timeout=2) as r:
                    return bool(json.loads(r.read())["status"] == "ok")
            except OSError:
                return False

        wait_until(up, 60, "melfa serve to answer")
        workers = wait_until(lambda: children(proc.pid), 30, "the server's worker processes")
        proc.send_signal(signal.SIGKILL)
        proc.wait(30)
        wait_until(
            lambda: not any(running(pid) for pid in workers),
            30,
            what=lambda: f"workers {[p for p in workers if running(p)]} to exit",
        )
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for pid in workers if "workers" in locals() else []:
            if running(pid):
                os.kill(pid, signal.SIGKILL)
