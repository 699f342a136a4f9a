"""`GET /api/health` (no sign-in): is the web process up, can the store be read, and how
is the robot link."""

from __future__ import annotations

import logging

from fastapi import APIRouter

from melfa import __version__
from melfa.service import LinkStatus
from melfa.web.deps import ContextDep
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import HealthOut, RobotHealth

router = APIRouter(prefix="/api", tags=["health"], responses=ERROR_RESPONSES)
_log = logging.getLogger("melfa.web")


@router.get("/health", response_model=HealthOut, summary="Health of web, store and robot")
async def health(context: ContextDep) -> HealthOut:
    try:
        await context.db(context.store.accounts.count_users)
        store = "ok"
    except Exception as exc:
        _log.warning("health: store unreadable: %s", exc)
        store = f"failing: {exc}"
    link = context.service.link_status
    robot = RobotHealth(
        link=link.value, robot=context.settings.robot, subscribers=context.service.subscribers
    )
    ok = store == "ok" and link is LinkStatus.CONNECTED
    return HealthOut(
        status="ok" if ok else "degraded", version=__version__, web="ok", store=store, robot=robot
    )


__all__ = ["router"]
