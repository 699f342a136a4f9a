"""No request waits in FastAPI's shared thread pool for a dependency: every dependency of
every route is ``async def``. FastAPI runs a plain ``def`` one in the pool it shares
among all requests, and under a class a STOP from REST waited there (p95 655 ms) before
its route ran; `web/deps.py` was made async for that, and a route module's own
dependency must be too."""

from __future__ import annotations

import inspect
from collections.abc import Iterator
from typing import Any

from fastapi.dependencies.models import Dependant
from fastapi.routing import APIRoute, APIWebSocketRoute

from melfa.store import Store
from melfa.web import WebSettings, create_app


def _routes(routes: list[Any]) -> Iterator[APIRoute | APIWebSocketRoute]:
    """Every route, those of included routers too (FastAPI keeps an included router whole,
    as its ``original_router``)."""
    for route in routes:
        if isinstance(route, APIRoute | APIWebSocketRoute):
            yield route
        included = getattr(route, "original_router", None)
        if included is not None:
            yield from _routes(included.routes)


def _calls(dependant: Dependant) -> Iterator[Any]:
    for sub in dependant.dependencies:
        yield sub.call
        yield from _calls(sub)


def test_every_dependency_of_every_route_is_async(store: Store, tmp_path: Any) -> None:
    app = create_app(WebSettings(data_dir=tmp_path / "data"), store=store)
    routes = list(_routes(app.routes))
    assert len(routes) > 100  # the app's routes, not an empty list
    plain = {
        f"{call.__module__}.{call.__qualname__}"
        for route in routes
        for call in _calls(route.dependant)
        if not inspect.iscoroutinefunction(call)
    }
    assert plain == set()
