"""`/api/runs`: the recorded runs of the lab robot (`melfa.web.recorded_runs`). A student
sees their own runs, instructors and admins everyone's: `may_see` is the one place that
decides, and every route asks it. A run another student made answers 404, as one that does
not exist (nobody learns whose runs there are)."""

from __future__ import annotations

import datetime as dt
from typing import Annotated

from fastapi import APIRouter, Path, Query
from pydantic import BaseModel, Field

from melfa.service.recording_compare import unpack
from melfa.service.recording_frames import EncodingError, decode
from melfa.store import User
from melfa.store.errors import NotFound
from melfa.store.runs import MAX_PAGE, Run, RunInfo
from melfa.vocab.runs import RunOutcome
from melfa.web.context import WebContext
from melfa.web.deps import ContextDep, SessionDep, StaffDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Input

router = APIRouter(prefix="/api/runs", tags=["runs"], responses=ERROR_RESPONSES)


def may_see(user: User, owner: str) -> bool:
    """Whether ``user`` may see a run ``owner`` made: their own, or any for staff."""
    return user.role.is_staff or user.username.casefold() == owner.casefold()


class DeviationOut(BaseModel):
    mm: float = Field(description="The largest distance of the real TCP from the simulated path.")
    t: float = Field(description="When (s since the run began).")
    line: int | None = Field(description="The line of the student's text running then.")
    real: list[float] = Field(description="The real TCP there, X, Y, Z (mm).")
    simulated: list[float] = Field(description="The nearest simulated point, X, Y, Z (mm).")


class RunReportOut(BaseModel):
    """Real against simulated: the real TCP is compared, sample by sample, with the
    simulated path of the same line (and its neighbours), not at the same time."""

    deviation: DeviationOut | None = Field(
        None, description="None: no simulated path, or no sample with a pose and a line."
    )
    compared: int = Field(0, description="Real samples compared.")
    cycle_difference: float | None = Field(
        None, description="Real minus simulated cycle time (s); None when either is unknown."
    )


class RunSummaryOut(BaseModel):
    id: int
    target: str = Field(description="The shared robot (``lab``).")
    user: str = Field(description="Who ran it.")
    started: dt.datetime
    duration: float = Field(description="Seconds from RUN to the end of the recording.")
    outcome: RunOutcome
    fingerprint: str | None = Field(description="The program and points as sent (the gate's).")
    frame_count: int
    frames_bytes: int | None = Field(description="Stored size of the samples; None: thinned.")
    thinned: bool = Field(description="Old run: samples gone, summary kept.")
    simulated_by: str | None = Field(description="Whose passed pre-flight it is compared with.")
    cycle_real: float | None = Field(description="Cycle time of a finished run (s).")
    cycle_simulated: float | None
    report: RunReportOut
    kept: bool = Field(description="Kept from thinning by an instructor.")


class FramesOut(BaseModel):
    """The samples, one list per field (index i of each is sample i)."""

    t: list[float]
    joints: list[list[float] | None]
    pose: list[list[float] | None]
    line: list[int | None] = Field(description="The student's line running.")
    hand: list[bool | None] = Field(description="Hand 1: open, closed or unknown.")
    alarm: list[int | None]
    override: list[int | None]
    running: list[bool]


class SimulatedOut(BaseModel):
    cycle_time: float | None
    path: list[list[float | int | None]] = Field(description="``[t, x, y, z, line]`` samples.")


class RunOut(RunSummaryOut):
    loaded_by: str | None
    program: str | None = Field(description="The student's text that ran (the lines refer to it).")
    frames: FramesOut | None = Field(description="None once thinned.")
    simulated: SimulatedOut | None


class KeepIn(Input):
    kept: bool = True


def _summary(info: RunInfo) -> dict[str, object]:
    return {
        "id": info.id,
        "target": info.target,
        "user": info.username,
        "started": info.started,
        "duration": info.duration,
        "outcome": info.outcome,
        "fingerprint": info.fingerprint,
        "frame_count": info.frame_count,
        "frames_bytes": info.frames_bytes,
        "thinned": info.thinned,
        "simulated_by": info.simulated_by,
        "cycle_real": info.cycle_real,
        "cycle_simulated": info.cycle_simulated,
        "report": RunReportOut.model_validate(info.report or {}),
        "kept": info.kept,
    }


def _frames(data: bytes | None) -> FramesOut | None:
    if data is None:
        return None
    frames = decode(data)
    return FramesOut(
        t=[f.t for f in frames],
        joints=[list(f.joints) if f.joints else None for f in frames],
        pose=[list(f.pose) if f.pose else None for f in frames],
        line=[f.line for f in frames],
        hand=[f.hands[0] for f in frames],
        alarm=[f.alarm for f in frames],
        override=[f.override for f in frames],
        running=[f.running for f in frames],
    )


def _run_out(run: Run) -> RunOut:
    simulated = None
    if run.simulated is not None:
        sim = unpack(run.simulated)
        simulated = SimulatedOut(
            cycle_time=sim.cycle_time, path=[[s.t, s.x, s.y, s.z, s.line] for s in sim.path]
        )
    try:
        frames = _frames(run.frames)
    except EncodingError:
        frames = None
    return RunOut(
        **_summary(run.info),  # type: ignore[arg-type]
        loaded_by=run.loaded_by,
        program=run.program,
        frames=frames,
        simulated=simulated,
    )


async def _visible(context: WebContext, user: User, run_id: int) -> Run:
    try:
        run = await context.db(context.store.runs.get, run_id)
    except NotFound:
        run = None
    if run is None or not may_see(user, run.info.username):
        raise ApiError(404, "not-found", f"there is no run {run_id} of yours")
    return run


@router.get("", response_model=list[RunSummaryOut], summary="Recorded runs, newest first")
async def list_runs(
    session: SessionDep,
    context: ContextDep,
    user: Annotated[
        str | None, Query(description="Whose runs (instructors: anyone's; default all)")
    ] = None,
    before: Annotated[
        int | None, Query(ge=1, le=2**62, description="Older than this run id (paging)")
    ] = None,
    limit: Annotated[int, Query(ge=1, le=MAX_PAGE)] = 50,
) -> list[RunSummaryOut]:
    """A student's own runs; an instructor's list holds everyone's (or ``user``'s)."""
    me = session.user
    if not me.role.is_staff:
        if user is not None and not may_see(me, user):
            raise ApiError(403, "forbidden", "you can see only your own runs")
        user = me.username
    infos = await context.db(context.store.runs.list, user, before=before, limit=limit)
    return [RunSummaryOut(**_summary(i)) for i in infos]  # type: ignore[arg-type]


RunId = Annotated[int, Path(ge=1, le=2**62, description="The run's id")]
"""A run's id in a path: SQLite's integers end at 2**63 (a larger one was a 500)."""


@router.get("/{run_id}", response_model=RunOut, summary="One run with its samples")
async def get_run(run_id: RunId, session: SessionDep, context: ContextDep) -> RunOut:
    """The summary, the student's text, every sample (for the replay) and the simulated
    path it is compared with."""
    run = await _visible(context, session.user, run_id)
    return await context.cpu(_run_out, run)


@router.put("/{run_id}/kept", response_model=RunSummaryOut, summary="Keep a run from thinning")
async def keep_run(
    run_id: RunId, body: KeepIn, session: StaffDep, context: ContextDep
) -> RunSummaryOut:
    """Instructors: keep a run's samples whatever thinning comes later (or stop keeping)."""
    await _visible(context, session.user, run_id)
    await context.db(context.store.runs.keep, run_id, body.kept)
    run = await context.db(context.store.runs.get, run_id)
    return RunSummaryOut(**_summary(run.info))  # type: ignore[arg-type]


__all__ = ["may_see", "router"]
