"""The HTTP side of the web API (docs/api.md) for the desktop client. Pure: no Qt.

Standard library only (`urllib`): the `desktop` extra adds PySide6 and nothing else.
One `ApiClient` is one signed-in session: it keeps the session cookie and sends the CSRF
token (``X-CSRF-Token``) on every state-changing request, as the browser does. Calls are
blocking and thread-safe (no shared connection), so the presenter runs them off the GUI
thread. Failures are typed by whose fault they are: `ApiError` (the server or the
controller refused; it carries the API's one error shape) or `ServerUnreachable` (the
network or the server process).
"""

from __future__ import annotations

import enum
import json
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Mapping
from dataclasses import dataclass, field
from http.cookies import SimpleCookie
from typing import Any

from melfa.desktop.messages import parse_fix, read_state
from melfa.live.messages import StateOut
from melfa.protocol.advice import Fix
from melfa.vocab.targets import TARGET_LABELS as VOCAB_TARGET_LABELS

SESSION_COOKIE = "melfa_session"
"""The server's HttpOnly session cookie (docs/api.md, Auth)."""
CSRF_HEADER = "X-CSRF-Token"
DEFAULT_SERVER = "http://127.0.0.1:8080"
DEFAULT_TIMEOUT_S = 30.0
"""Per socket operation; robot commands answer only after the controller did."""
LONG_TIMEOUT_S = 300.0
"""Uploads over a 9600 baud link take a while; a long program may take minutes."""
STOP_TIMEOUT_S = 10.0


class Severity(enum.Enum):
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Diagnostic:
    """One finding of `/api/check` (the shape of `melfa check --format json`)."""

    line: int
    column: int
    severity: Severity
    message: str
    code: str | None = None
    suggestion: str | None = None

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Diagnostic:
        try:
            severity = Severity(data.get("severity"))
        except ValueError:
            severity = Severity.ERROR
        return cls(
            line=int(data.get("line") or 0),
            column=int(data.get("column") or 0),
            severity=severity,
            message=str(data.get("message") or ""),
            code=data.get("code") if isinstance(data.get("code"), str) else None,
            suggestion=data.get("suggestion") if isinstance(data.get("suggestion"), str) else None,
        )

    def __str__(self) -> str:
        """
        >>> str(Diagnostic(2, 4, Severity.ERROR, "Invalid statement"))
        '2:4 error: Invalid statement'
        """
        return f"{self.line}:{self.column} {self.severity.value}: {self.message}"


def _diagnostics(value: object) -> tuple[Diagnostic, ...]:
    if not isinstance(value, list):
        return ()
    return tuple(Diagnostic.from_json(d) for d in value if isinstance(d, Mapping))


@dataclass(frozen=True)
class CheckResult:
    program: tuple[Diagnostic, ...]
    points: tuple[Diagnostic, ...]

    @property
    def program_errors(self) -> tuple[Diagnostic, ...]:
        return tuple(d for d in self.program if d.severity is Severity.ERROR)

    @property
    def points_errors(self) -> tuple[Diagnostic, ...]:
        return tuple(d for d in self.points if d.severity is Severity.ERROR)

    @property
    def ok(self) -> bool:
        return not self.program_errors and not self.points_errors


@dataclass(frozen=True)
class SignedIn:
    username: str
    display_name: str
    role: str


@dataclass(frozen=True)
class WorkspaceInfo:
    """One workspace the user may open (`GET /api/workspaces`)."""

    id: int
    name: str
    shared: bool


@dataclass(frozen=True)
class WorkspaceTexts:
    id: int
    name: str
    program: str
    points: str


@dataclass(frozen=True)
class UploadReport:
    items: int
    requests: int
    bytes_sent: int
    seconds: float
    step_lines: dict[int, int] = field(default_factory=dict)
    """Step number the controller reports -> line of the program file (the server's map)."""


class ApiError(Exception):
    """The server answered with its error shape: a refusal (4xx: ours or the controller's),
    the robot link (503) or the server's own failure (5xx)."""

    def __init__(
        self,
        status: int,
        code: str,
        message: str,
        where: Mapping[str, Any] | None = None,
        detail: Mapping[str, Any] | None = None,
    ) -> None:
        super().__init__(f"{message} ({code}, HTTP {status})")
        self.status = status
        self.code = code
        self.message = message
        self.where = dict(where) if where else None
        self.detail = dict(detail) if detail else None

    @property
    def fix(self) -> Fix | None:
        """The one action that fixes it (``detail.fix``), offered as a button."""
        return parse_fix((self.detail or {}).get("fix"))

    @property
    def error_code(self) -> str:
        """The controller's number as the manual lists it (``L2000``), or ""."""
        code = (self.detail or {}).get("code")
        return code if isinstance(code, str) else ""

    @property
    def diagnostics(self) -> tuple[Diagnostic, ...]:
        """Refusals of a program or points carry their diagnostics (`program-has-errors`)."""
        return _diagnostics((self.detail or {}).get("diagnostics"))

    @classmethod
    def from_body(cls, status: int, body: bytes) -> ApiError:
        """
        >>> e = ApiError.from_body(401, b'{"error": {"code": "wrong-login", "status": 401,'
        ...                             b' "message": "Wrong username or password"}}')
        >>> e.code, e.message
        ('wrong-login', 'Wrong username or password')
        >>> ApiError.from_body(502, b"<html>Bad gateway</html>").code
        'http-502'
        """
        try:
            error = json.loads(body.decode("utf-8"))["error"]
            return cls(
                int(error.get("status") or status),
                str(error["code"]),
                str(error.get("message") or error["code"]),
                error.get("where") if isinstance(error.get("where"), Mapping) else None,
                error.get("detail") if isinstance(error.get("detail"), Mapping) else None,
            )
        except (ValueError, KeyError, TypeError, AttributeError):
            text = body.decode("utf-8", errors="replace").strip()[:200]
            return cls(status, f"http-{status}", text or f"HTTP {status} without a body")


class ServerUnreachable(Exception):
    """No answer: the server is not running there, the network failed, or it timed out."""

    def __init__(self, url: str, reason: str) -> None:
        super().__init__(f"cannot reach {url}: {reason}")
        self.url = url
        self.reason = reason


LAB_TARGET = "lab"
PRIVATE_TARGET = "mine"
TARGET_LABELS = {target: VOCAB_TARGET_LABELS[target] for target in (LAB_TARGET, PRIVATE_TARGET)}
"""The robots a user may drive (the server's docs/api.md "Targets")."""


def normalize_server(url: str) -> str:
    """``host:port`` or a full http(s) URL, without a trailing slash; ValueError otherwise.

    >>> normalize_server("127.0.0.1:8080"), normalize_server("https://lab.example/melfa/")
    ('http://127.0.0.1:8080', 'https://lab.example/melfa')
    """
    text = url.strip()
    if "://" not in text:
        text = "http://" + text
    parts = urllib.parse.urlsplit(text)
    if parts.scheme not in ("http", "https") or not parts.hostname:
        raise ValueError(f"not a server address: {url!r} (expected http://host:port)")
    return urllib.parse.urlunsplit((parts.scheme, parts.netloc, parts.path.rstrip("/"), "", ""))


def websocket_url(server: str) -> str:
    """
    >>> websocket_url("http://127.0.0.1:8080"), websocket_url("https://lab.example/m")
    ('ws://127.0.0.1:8080/api/ws', 'wss://lab.example/m/api/ws')
    """
    scheme, rest = server.split("://", 1)
    return ("wss" if scheme == "https" else "ws") + "://" + rest + "/api/ws"


# Talk to the server directly: a lab PC's proxy settings are for the internet, not the LAN.
_OPENER = urllib.request.build_opener(urllib.request.ProxyHandler({}))


class ApiClient:
    """One session with one server. `login` first; then every call acts as that user."""

    def __init__(self, server: str = DEFAULT_SERVER, timeout: float = DEFAULT_TIMEOUT_S) -> None:
        self.server = normalize_server(server)
        self.timeout = timeout
        self._session: str | None = None
        self._csrf: str | None = None
        self.user: SignedIn | None = None
        self.target = LAB_TARGET
        """Which robot `/api/robot/…` calls and the live feed drive: ``lab`` or ``mine``."""

    @property
    def signed_in(self) -> bool:
        return self._session is not None

    @property
    def websocket_url(self) -> str:
        url = websocket_url(self.server)
        return url if self.target == LAB_TARGET else f"{url}?target={self.target}"

    def targeted(self, path: str) -> str:
        """``path`` with ``?target=`` when it drives a robot other than the lab's."""
        if not path.startswith("/api/robot/") or self.target == LAB_TARGET:
            return path
        return f"{path}{'&' if '?' in path else '?'}target={self.target}"

    def cookie_header(self) -> dict[str, str]:
        """The header that authenticates the WebSocket (the session cookie)."""
        return {"Cookie": f"{SESSION_COOKIE}={self._session}"} if self._session else {}

    # --- transport --------------------------------------------------------------------

    def _request(
        self,
        method: str,
        path: str,
        body: Mapping[str, Any] | None = None,
        timeout: float | None = None,
    ) -> tuple[Any, list[str]]:
        """(JSON reply, Set-Cookie headers) or `ApiError` / `ServerUnreachable`."""
        url = self.server + self.targeted(path)
        headers = {"Accept": "application/json", **self.cookie_header()}
        data = None
        if body is not None:
            data = json.dumps(body).encode("utf-8")
            headers["Content-Type"] = "application/json"
        if method not in ("GET", "HEAD") and self._csrf:
            headers[CSRF_HEADER] = self._csrf
        request = urllib.request.Request(url, data=data, headers=headers, method=method)
        try:
            with _OPENER.open(request, timeout=timeout or self.timeout) as reply:
                raw = reply.read()
                cookies = reply.headers.get_all("Set-Cookie") or []
        except urllib.error.HTTPError as exc:
            with exc:
                raise ApiError.from_body(exc.code, exc.read()) from None
        except urllib.error.URLError as exc:
            reason = exc.reason
            text = reason.strerror if isinstance(reason, OSError) and reason.strerror else reason
            raise ServerUnreachable(self.server, str(text)) from None
        except TimeoutError:
            raise ServerUnreachable(self.server, "no answer in time") from None
        except OSError as exc:
            raise ServerUnreachable(self.server, str(exc.strerror or exc)) from None
        try:
            return (json.loads(raw.decode("utf-8")) if raw else None), cookies
        except ValueError:
            raise ApiError(502, "bad-reply", f"the server's reply to {path} is not JSON") from None

    def _call(
        self,
        method: str,
        path: str,
        body: Mapping[str, Any] | None = None,
        timeout: float | None = None,
    ) -> Any:
        return self._request(method, path, body, timeout)[0]

    # --- session ----------------------------------------------------------------------

    def health(self) -> dict[str, Any]:
        """`GET /api/health` (no sign-in needed)."""
        reply = self._call("GET", "/api/health", timeout=min(self.timeout, 5.0))
        return dict(reply) if isinstance(reply, Mapping) else {}

    def login(self, username: str, password: str) -> SignedIn:
        """`POST /api/session`; keeps the session cookie and the CSRF token."""
        reply, cookies = self._request(
            "POST", "/api/session", {"username": username, "password": password}
        )
        token = None
        for header in cookies:
            jar: SimpleCookie = SimpleCookie()
            jar.load(header)
            if SESSION_COOKIE in jar:
                token = jar[SESSION_COOKIE].value
        if token is None or not isinstance(reply, Mapping):
            raise ApiError(502, "bad-reply", "the server signed us in without a session cookie")
        self._session = token
        self._csrf = str(reply.get("csrf_token") or "")
        user = reply.get("user") or {}
        self.user = SignedIn(
            username=str(user.get("username") or username),
            display_name=str(user.get("display_name") or ""),
            role=str(user.get("role") or ""),
        )
        return self.user

    def logout(self) -> None:
        """`DELETE /api/session`; forgets the session even when the server is gone."""
        try:
            if self._session:
                self._call("DELETE", "/api/session", timeout=min(self.timeout, 5.0))
        finally:
            self._session = self._csrf = None
            self.user = None

    # --- checking and robot -------------------------------------------------------------

    def check(self, program: str, points: str) -> CheckResult:
        """`POST /api/check`: the program against the points' names, and the points."""
        reply = self._call("POST", "/api/check", {"program": program, "points": points})
        return CheckResult(
            program=_diagnostics((reply.get("program") or {}).get("diagnostics")),
            points=_diagnostics((reply.get("points") or {}).get("diagnostics")),
        )

    def load_project(self, program: str, points: str) -> UploadReport:
        """`POST /api/robot/project`: program and points into slot 1 in one session."""
        reply = self._call(
            "POST",
            "/api/robot/project",
            {"program": program, "points": points, "check": True},
            timeout=LONG_TIMEOUT_S,
        )
        return UploadReport(
            items=int(reply.get("items") or 0),
            requests=int(reply.get("requests") or 0),
            bytes_sent=int(reply.get("bytes_sent") or 0),
            seconds=float(reply.get("seconds") or 0.0),
            step_lines={int(k): int(v) for k, v in (reply.get("step_lines") or {}).items()},
        )

    def run(self) -> None:
        """`POST /api/robot/run`: start the loaded program."""
        self._call("POST", "/api/robot/run", {"servo_on": True}, timeout=LONG_TIMEOUT_S)

    def claim(self) -> None:
        """`POST /api/queue/claim`: take the lab robot's arm when the queue offers it; the
        queued program loads and runs."""
        self._call("POST", "/api/queue/claim", {"start": True})

    def stop(self) -> None:
        """`POST /api/robot/stop`: allowed to everyone, overtakes queued commands."""
        self._call("POST", "/api/robot/stop", {}, timeout=STOP_TIMEOUT_S)

    def reset_alarm(self) -> None:
        """`POST /api/robot/reset-alarm` (RSTALRM): clear the controller's error."""
        self._call("POST", "/api/robot/reset-alarm", {})

    def servo(self, on: bool) -> None:
        """`POST /api/robot/servo`."""
        self._call("POST", "/api/robot/servo", {"on": on})

    def override(self, percent: int) -> int:
        """`POST /api/robot/override` (1–100 %); returns the value the controller took."""
        reply = self._call("POST", "/api/robot/override", {"percent": percent})
        return int(reply["percent"]) if isinstance(reply, Mapping) else percent

    def jog_step(self, frame: str, axis: int, direction: int) -> None:
        """`POST /api/robot/jog-step`: one increment. Pressing a jog button is asking to
        move, so a servo that is off is switched on first (audited by the server)."""
        body = {"frame": frame, "axis": axis, "direction": direction, "servo_on": True}
        self._call("POST", "/api/robot/jog-step", body, timeout=LONG_TIMEOUT_S)

    def exec_statement(self, statement: str) -> None:
        """`POST /api/robot/exec`: one MELFA BASIC statement."""
        self._call("POST", "/api/robot/exec", {"statement": statement}, timeout=LONG_TIMEOUT_S)

    def workspaces(self) -> tuple[WorkspaceInfo, ...]:
        """`GET /api/workspaces`: the user's own, their group's, the default first."""
        reply = self._call("GET", "/api/workspaces")
        rows = [w for w in (reply or {}).get("workspaces") or [] if isinstance(w, Mapping)]
        default = (reply or {}).get("default_id")
        rows.sort(key=lambda w: w.get("id") != default)
        return tuple(
            WorkspaceInfo(int(w["id"]), str(w.get("name") or ""), bool(w.get("shared")))
            for w in rows
            if not w.get("archived")
        )

    def workspace(self, workspace_id: int) -> WorkspaceTexts:
        """`GET /api/workspaces/{id}`: its name and its latest program and points."""
        reply = self._call("GET", f"/api/workspaces/{workspace_id}")
        return WorkspaceTexts(
            workspace_id,
            str(reply.get("name") or ""),
            str(reply.get("program") or ""),
            str(reply.get("points") or ""),
        )

    def state(self) -> StateOut:
        """`GET /api/robot/state`: the latest snapshot (no round trip to the robot)."""
        reply = self._call("GET", "/api/robot/state")
        return read_state(reply)


__all__ = [
    "CSRF_HEADER",
    "DEFAULT_SERVER",
    "SESSION_COOKIE",
    "ApiClient",
    "ApiError",
    "CheckResult",
    "Diagnostic",
    "ServerUnreachable",
    "Severity",
    "SignedIn",
    "UploadReport",
    "WorkspaceInfo",
    "WorkspaceTexts",
    "normalize_server",
    "websocket_url",
]
