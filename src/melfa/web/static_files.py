"""The IDE's static files, compressed and cached: the first load of the IDE is well under
1 MB on the wire (gzip, `app.py`), and a reload transfers next to nothing.

- ``/static/vendor/…``: the pinned libraries live under versioned paths
  (``three-0.187.0/``), so they never change in place: cached for a year, immutable.
- everything else (the IDE's own modules, CSS): ``no-cache``, i.e. the browser keeps its
  copy and revalidates it with the ETag (a bodiless 304 when unchanged), so a new release
  is seen at once.
"""

from __future__ import annotations

import os
from typing import Any

from starlette.responses import Response
from starlette.staticfiles import StaticFiles
from starlette.types import Scope

IMMUTABLE = "public, max-age=31536000, immutable"
REVALIDATE = "no-cache"


class CachedStaticFiles(StaticFiles):
    """`StaticFiles` with the Cache-Control rule above."""

    def file_response(
        self,
        full_path: str | os.PathLike[str],
        stat_result: os.stat_result,
        scope: Scope,
        status_code: int = 200,
    ) -> Response:
        response = super().file_response(full_path, stat_result, scope, status_code)
        path = str(scope.get("path", ""))
        response.headers["Cache-Control"] = IMMUTABLE if "/vendor/" in path else REVALIDATE
        return response


def cache_headers(response: Any, immutable: bool = False) -> None:
    """The same rule for pages served outside ``/static`` (the favicon)."""
    response.headers["Cache-Control"] = IMMUTABLE if immutable else REVALIDATE


__all__ = ["IMMUTABLE", "REVALIDATE", "CachedStaticFiles", "cache_headers"]
