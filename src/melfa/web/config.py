"""Settings of the web server, in one checked object (the FastAPI template's core/config)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from melfa.service import ServiceConfig
from melfa.service.lab_network import Network
from melfa.service.queue import QueueSettings
from melfa.web.coedit import CoeditSettings
from melfa.web.limits import Limits
from melfa.web.pools import PoolSizes

SESSION_COOKIE = "melfa_session"
"""HttpOnly cookie holding the session token."""
CSRF_COOKIE = "melfa_csrf"
"""Readable cookie holding the session's CSRF token (double submit: send it back as
the `X-CSRF-Token` header on every state-changing request)."""
CSRF_HEADER = "X-CSRF-Token"
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})


@dataclass(frozen=True)
class WebSettings:
    """What `create_app` needs; `melfa serve` fills it from its options."""

    data_dir: Path = Path("data")
    """Holds melfa.sqlite3 (accounts, sessions, workspaces, audit)."""
    robot: str = "sim"
    """A ``--robot`` spec; ``sim`` is the in-process virtual controller (real time)."""
    robot_trace: Path | None = None
    """``--trace FILE``: every byte to and from the robot, with timestamps (replayable)."""
    allowed_origins: tuple[str, ...] = ()
    """Extra browser origins allowed to open the WebSocket, sign in and send forms (the
    page's own always is; ``null`` never)."""
    allowed_hosts: tuple[str, ...] = ()
    """Host names the server answers to (others: 421), against DNS rebinding; empty: any.
    `melfa serve` on a loopback address allows only localhost, 127.0.0.1 and ::1."""
    trusted_proxies: tuple[str, ...] = ()
    """Addresses of reverse proxies whose X-Forwarded-For/-Proto are believed (none)."""
    limits: Limits = field(default_factory=Limits)
    pools: PoolSizes = field(default_factory=PoolSizes)
    snapshot_hz: float = 20.0
    """Most state snapshots per second sent to one WebSocket (newest wins)."""
    secure_cookies: bool | None = None
    """Mark cookies Secure: None decides per request (https → Secure)."""
    service_config: ServiceConfig = field(default_factory=ServiceConfig)
    private_idle_s: float = 1800.0
    """A private simulator nobody used (no request, no open socket) for this long is freed;
    its owner's programs stay in the workspace and a new one is made on next use."""

    coedit: CoeditSettings = field(default_factory=CoeditSettings)
    """When a live document becomes a revision; when a silent editor is let go."""

    require_simulation: bool = False
    """The instructor's gate: the lab robot loads and runs a program only after the same
    text passed a simulated run without pre-flight errors (docs/ide.md)."""
    lab_networks: tuple[Network, ...] = ()
    """Where the lab robot may be driven from (``--lab-network``; empty: anywhere); staff
    switch it live on the instructor's desk (`melfa.service.lab_network`)."""
    queue: QueueSettings = field(default_factory=QueueSettings)
    """The lab robot's queue: claim window, turn length, grace time, a turn's end."""

    def __post_init__(self) -> None:
        if not 0.5 <= self.snapshot_hz <= 200:
            raise ValueError("snapshot_hz must be 0.5–200 per second")
        if self.private_idle_s <= 0:
            raise ValueError("private_idle_s must be positive")


__all__ = [
    "CSRF_COOKIE",
    "CSRF_HEADER",
    "SAFE_METHODS",
    "SESSION_COOKIE",
    "WebSettings",
]
