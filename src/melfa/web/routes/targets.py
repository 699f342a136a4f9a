"""`/api/targets`: the robots the caller may drive (the lab's, and their own simulator)."""

from __future__ import annotations

from fastapi import APIRouter

from melfa.web.convert import target_out
from melfa.web.deps import ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES
from melfa.web.models import TargetOut, TargetsOut
from melfa.web.targets import MINE, PRIVATE_LABEL, TargetKind

router = APIRouter(prefix="/api/targets", tags=["targets"], responses=ERROR_RESPONSES)


@router.get("", response_model=TargetsOut, summary="The robots you may drive")
async def list_targets(session: SessionDep, context: ContextDep) -> TargetsOut:
    """The lab robot and your private simulator (made when first used: pass
    ``?target=mine`` to any robot route, or open ``/api/ws?target=mine``)."""
    targets = context.targets
    lab = target_out(targets.lab, robot=context.settings.robot)
    mine = targets.private(session.user.username)
    if mine is None:  # listing does not make one: using it does
        out = TargetOut(
            id=MINE,
            kind=TargetKind.PRIVATE.value,
            label=PRIVATE_LABEL,
            shared=False,
            robot="sim",
            exists=False,
            link=None,
        )
    else:
        out = target_out(mine, robot="sim")
    return TargetsOut(targets=[lab, out], idle_s=targets.idle_s)


__all__ = ["router"]
