"""melfa.web: the ASGI app behind `melfa serve` and the browser IDE.

- `create_app(WebSettings(...))`: FastAPI app with login (cookie session + CSRF token),
  workspaces, checking, every robot operation of `melfa.service`, the lease, the audit
  log, user management, health, and one WebSocket per browser for live state and jog.
- One error shape for every failure (`melfa.web.errors`), documented in docs/api.md.

What it does not do: talk to the controller (the service does), keep data (the store
does), or build the IDE's JavaScript (issue 7, in ``static/``).
"""

from melfa.web.app import create_app
from melfa.web.config import CSRF_COOKIE, CSRF_HEADER, SESSION_COOKIE, WebSettings

__all__ = ["CSRF_COOKIE", "CSRF_HEADER", "SESSION_COOKIE", "WebSettings", "create_app"]
