"""Pages outside the JSON API: the IDE's placeholder index (issue 7 replaces it) and
`/docs`, a self-contained list of every operation (no CDN: the lab may have no internet)."""

from __future__ import annotations

import html
from pathlib import Path

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse, HTMLResponse, RedirectResponse, Response

from melfa.web.config import SESSION_COOKIE
from melfa.web.context import WebContext
from melfa.web.deps import find_session

router = APIRouter(include_in_schema=False)
STATIC = Path(__file__).resolve().parent.parent / "static"


@router.get("/", response_model=None)
async def index(request: Request) -> Response:
    context: WebContext = request.app.state.web
    session = await find_session(context, request.cookies.get(SESSION_COOKIE))
    if session is None:
        return RedirectResponse("/login", status_code=303)
    request.state.user = session.user.username
    return FileResponse(STATIC / "index.html", media_type="text/html")


@router.get("/docs")
async def docs(request: Request) -> HTMLResponse:
    spec = request.app.openapi()
    e = html.escape
    rows = []
    for path, item in spec.get("paths", {}).items():
        for method, op in item.items():
            rows.append(
                f"<tr><td><code>{e(method.upper())}</code></td><td><code>{e(path)}</code></td>"
                f"<td>{e(op.get('summary', ''))}</td><td><code>{e(op.get('operationId', ''))}"
                "</code></td></tr>"
            )
    body = f"""<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>melfa API</title>
<style>body{{font:14px system-ui,sans-serif;margin:1.5em}}td,th{{padding:.2em .6em;
text-align:left;border-bottom:1px solid #ddd}}</style></head><body>
<h1>{e(spec.get("info", {}).get("title", "API"))} {e(spec.get("info", {}).get("version", ""))}</h1>
<p>The full OpenAPI description: <a href="/openapi.json">/openapi.json</a>. Errors share one
shape: <code>{{"error": {{"code", "message", "status", "where", "detail"}}}}</code>.
State-changing requests need the <code>X-CSRF-Token</code> header. Live state:
WebSocket <code>/api/ws</code> (see docs/api.md).</p>
<table><thead><tr><th>method</th><th>path</th><th>what</th><th>operation id</th></tr></thead>
<tbody>{"".join(rows)}</tbody></table></body></html>"""
    return HTMLResponse(body)


__all__ = ["router"]
