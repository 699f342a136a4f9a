"""Co-editing benchmark: edit-to-partner latency for pairs typing in their group's
workspace at once (issue 26).

Starts a real `melfa serve` (a subprocess, its own temporary data folder) with one group
of two students per pair, then every student opens the group's live document
(`/api/workspaces/{id}/live`) as a pycrdt document, the Python peer of the IDE's Yjs, and
types: one keystroke (a token of a few characters) every 1/rate seconds, at the end of
the program, both partners at once. Each keystroke's latency is from the moment the
typist's update is sent to the moment the partner's document, having applied the update
the server relayed, holds that keystroke. The clients run in this process, on the same
2 cores as the server. At the end both partners and the server's saved revision must hold
every keystroke of both (lost = any missing).

    .venv/bin/python bench/bench_coedit.py [--pairs 20] [--seconds 20] [--rate 5]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import re
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from base64 import b64decode, b64encode
from pathlib import Path

import httpx
from argon2 import PasswordHasher
from pycrdt import Doc, Text
from websockets.asyncio.client import ClientConnection, connect

from melfa.store import Store
from serving import wait_healthy

PASSWORD = "bench-password-1"
ADMIN_PASSWORD = "bench-admin-password-1"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def b64(data: bytes) -> str:
    return b64encode(data).decode()


class Typist:
    """One student: a pycrdt document on the live socket, typing tokens ``<name><n> ``."""

    def __init__(self, name: str, partner: str) -> None:
        self.name = name
        self.partner = partner
        self.doc: Doc[Text] = Doc()
        self.text = self.doc.get("program", type=Text)
        self.sent: dict[int, float] = {}
        self.seen: set[int] = set()
        self.latencies: list[float] = []
        self.pattern = re.compile(re.escape(partner) + r"(\d+) ")
        self.socket: ClientConnection | None = None
        self.other: Typist | None = None
        self.pinger: asyncio.Task[None]

    async def join(self, base: str, cookie: str, workspace: int) -> None:
        url = base.replace("http", "ws", 1) + f"/api/workspaces/{workspace}/live"
        self.socket = await connect(
            url, additional_headers={"cookie": cookie, "origin": base}, max_size=None
        )
        await self.socket.send(
            json.dumps({"type": "hello", "state_vector": b64(self.doc.get_state())})
        )
        while True:
            message = json.loads(await self.socket.recv())
            if message["type"] == "welcome":
                break
        self.doc.apply_update(b64decode(message["update"]))
        missing = self.doc.get_update(b64decode(message["state_vector"]))
        await self.socket.send(json.dumps({"type": "update", "update": b64(missing)}))
        self.pinger = asyncio.create_task(self.ping())

    async def ping(self) -> None:
        """Every 5 s, as the IDE does (a socket silent for 15 s is let go)."""
        assert self.socket is not None
        while True:
            await asyncio.sleep(5)
            await self.socket.send(json.dumps({"type": "ping"}))

    async def type(self, seconds: float, rate: float, start: float) -> None:
        assert self.socket is not None
        n = 0
        while time.monotonic() < start + seconds:
            due = start + n / rate
            await asyncio.sleep(max(0.0, due - time.monotonic()))
            before = self.doc.get_state()
            self.text.insert(len(str(self.text).encode()), f"{self.name}{n} ")
            update = self.doc.get_update(before)
            self.sent[n] = time.monotonic()
            await self.socket.send(json.dumps({"type": "update", "update": b64(update)}))
            n += 1

    async def listen(self) -> None:
        assert self.socket is not None and self.other is not None
        async for raw in self.socket:
            message = json.loads(raw)
            if message["type"] != "update":
                continue
            self.doc.apply_update(b64decode(message["update"]))
            now = time.monotonic()
            for match in self.pattern.finditer(str(self.text)):
                n = int(match.group(1))
                if n not in self.seen:
                    self.seen.add(n)
                    self.latencies.append(now - self.other.sent[n])


def make_accounts(data: Path, pairs: int) -> None:
    cheap = PasswordHasher(time_cost=1, memory_cost=64, parallelism=1)
    with Store.open_dir(data, hasher=cheap) as store:
        for p in range(pairs):
            for side in "ab":
                store.accounts.create_user(f"s{p}{side}", PASSWORD, group=f"Pair-{p}")


async def sign_in(client: httpx.AsyncClient, name: str) -> str:
    reply = await client.post("/api/session", json={"username": name, "password": PASSWORD})
    reply.raise_for_status()
    token = reply.cookies["melfa_session"]
    return f"melfa_session={token}"


async def run(base: str, pairs: int, seconds: float, rate: float) -> None:
    async with httpx.AsyncClient(base_url=base, timeout=60) as client:
        typists: list[tuple[Typist, Typist, int, str]] = []
        for p in range(pairs):
            a, b = Typist(f"s{p}a", f"s{p}b"), Typist(f"s{p}b", f"s{p}a")
            a.other, b.other = b, a
            cookie_a = await sign_in(client, a.name)
            cookie_b = await sign_in(client, b.name)
            listing = await client.get("/api/workspaces", headers={"cookie": cookie_a})
            workspace = int(listing.json()["default_id"])
            await a.join(base, cookie_a, workspace)
            await b.join(base, cookie_b, workspace)
            typists.append((a, b, workspace, cookie_a))
        everyone = [t for a, b, _, _ in typists for t in (a, b)]
        listeners = [asyncio.create_task(t.listen()) for t in everyone]
        start = time.monotonic() + 0.5
        await asyncio.gather(*(t.type(seconds, rate, start) for t in everyone))
        # Let the last edits arrive, then look at what everyone and the server hold.
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and any(
            len(t.seen) < len(t.other.sent) for t in everyone if t.other
        ):
            await asyncio.sleep(0.1)
        for task in listeners:
            task.cancel()
        lost = sum(len(t.other.sent) - len(t.seen) for t in everyone if t.other)
        diverged = sum(str(a.text) != str(b.text) for a, b, _, _ in typists)
        for t in everyone:
            assert t.socket is not None
            t.pinger.cancel()
            await t.socket.close()
        await asyncio.sleep(0.5)  # the last one out of each room saves it
        saved_missing = 0
        for a, b, workspace, cookie in typists:
            for _ in range(50):
                program = (
                    await client.get(f"/api/workspaces/{workspace}", headers={"cookie": cookie})
                ).json()["program"]
                if all(f"{t.name}{n} " in program for t in (a, b) for n in t.sent):
                    break
                await asyncio.sleep(0.2)
            saved_missing += sum(f"{t.name}{n} " not in program for t in (a, b) for n in t.sent)
    latencies = sorted(x * 1000 for t in everyone for x in t.latencies)
    q = statistics.quantiles(latencies, n=100)
    typed = sum(len(t.sent) for t in everyone)
    print(
        f"{pairs} pairs ({2 * pairs} typists), {rate:g} keys/s each, {seconds:g} s: {typed} edits"
    )
    print(
        f"edit to partner: p50 {q[49]:.1f} ms, p95 {q[94]:.1f} ms, max {latencies[-1]:.1f} ms "
        f"({len(latencies)} measured)"
    )
    print(
        f"lost at a partner: {lost}; pairs whose texts differ: {diverged}; "
        f"missing from the saved revisions: {saved_missing}"
    )
    print(f"load average during the run: {os.getloadavg()[0]:.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=20)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--rate", type=float, default=5.0, help="keystrokes per second each")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="melfa-bench-coedit-") as tmp:
        data = Path(tmp)
        make_accounts(data, args.pairs)
        port = free_port()
        env = {k: v for k, v in os.environ.items() if k not in ("MELFA_ROBOT", "MELFA_DATA")}
        env["MELFA_ADMIN_PASSWORD"] = ADMIN_PASSWORD
        log = (data / "serve.log").open("w")
        server = subprocess.Popen(
            [sys.executable, "-m", "melfa", "serve", "--port", str(port), "--data", str(data)],
            stdout=log,
            stderr=subprocess.STDOUT,
            env=env,
        )
        base = f"http://127.0.0.1:{port}"
        try:
            wait_healthy(base)
            asyncio.run(run(base, args.pairs, args.seconds, args.rate))
        finally:
            server.send_signal(signal.SIGINT)
            try:
                server.wait(timeout=20)
            except subprocess.TimeoutExpired:
                server.kill()
            log.close()


if __name__ == "__main__":
    main()
