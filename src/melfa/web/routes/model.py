"""The RV-6S model for the browser, from `melfa.kin` (one source for the kinematics):
``/model/rv6s.js`` (an ES module the 3D view imports: DH table, joint limits, home) and
``/model/rv6s.urdf`` (`melfa.ros.urdf`, for ROS tools fed over rosbridge); and the
controller's facts from `melfa.protocol`, ``/model/controller.js`` (axis names, hand numbers,
the override range), so the browser's scripts hold no copy of them."""

from __future__ import annotations

import json

from fastapi import APIRouter
from fastapi.responses import Response

from melfa.kin import DH, HOME, JOINT_LIMITS
from melfa.protocol import HANDS, JOINT_NAMES, OVERRIDE_PERCENT, POSE_NAMES
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


def controller_module() -> str:
    """The ES module text of the controller's facts."""
    facts: dict[str, object] = {
        "JOINT_NAMES": list(JOINT_NAMES),
        "POSE_NAMES": list(POSE_NAMES),
        "HANDS": {"min": HANDS.start, "max": HANDS[-1]},
        "OVERRIDE_PERCENT": {"min": OVERRIDE_PERCENT.start, "max": OVERRIDE_PERCENT[-1]},
    }
    lines = [
        f"export const {name} = Object.freeze({json.dumps(value)});"
        for name, value in facts.items()
    ]
    return (
        "// Generated from melfa.protocol (the controller's facts the server uses).\n"
        + "\n".join(lines)
        + "\n"
    )


@router.get("/model/controller.js")
async def controller_js() -> Response:
    return Response(controller_module(), media_type="text/javascript")


@router.get("/model/rv6s.js")
async def model_js() -> Response:
    return Response(model_module(), media_type="text/javascript")


@router.get("/model/rv6s.urdf")
async def model_urdf() -> Response:
    return Response(rv6s_urdf(), media_type="application/xml")


__all__ = ["controller_module", "model_module", "router"]
