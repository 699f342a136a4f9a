"""The RV-6S model for the browser, from `melfa.kin` (one source for the kinematics):
``/model/rv6s.js`` (an ES module the 3D view imports: DH table, joint limits, home) and
``/model/rv6s.urdf`` (`melfa.ros.urdf`, for ROS tools fed over rosbridge)."""

from __future__ import annotations

import json

from fastapi import APIRouter
from fastapi.responses import Response

from melfa.kin import DH, HOME, JOINT_LIMITS
from melfa.ros.urdf import rv6s_urdf

router = APIRouter(include_in_schema=False)


def model_module() -> str:
    """The ES module text."""
    rows = [{"a": r.a, "d": r.d, "alpha": r.alpha, "offset": r.offset} for r in DH]
    return (
        "// Generated from melfa.kin (the DH table the server's kinematics use).\n"
        f"export const DH = {json.dumps(rows)};\n"
        f"export const JOINT_LIMITS = {json.dumps([list(j) for j in JOINT_LIMITS])};\n"
        f"export const HOME = {json.dumps(list(HOME))};\n"
    )


@router.get("/model/rv6s.js")
async def model_js() -> Response:
    return Response(model_module(), media_type="text/javascript")


@router.get("/model/rv6s.urdf")
async def model_urdf() -> Response:
    return Response(rv6s_urdf(), media_type="application/xml")


__all__ = ["model_module", "router"]
