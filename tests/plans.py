"""Upload plans for tests: `melfa.lang.plan.plan_upload` with points given as a text or as
lines (as many tests keep them)."""

from __future__ import annotations

from collections.abc import Sequence

from melfa.lang.plan import UploadPlan, plan_upload


def _text(value: str | Sequence[str]) -> str:
    return value if isinstance(value, str) else "\n".join(value)


def project(program: str | Sequence[str], points: str | Sequence[str] = "") -> UploadPlan:
    """Program and points, as `load_project` takes them."""
    return plan_upload(_text(program), _text(points))


def program_plan(program: str | Sequence[str]) -> UploadPlan:
    """A program alone (`upload_program`)."""
    return plan_upload(_text(program))


def points_plan(points: str | Sequence[str]) -> UploadPlan:
    """Points alone (`upload_points`)."""
    return plan_upload(None, _text(points))
