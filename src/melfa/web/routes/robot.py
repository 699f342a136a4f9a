"""Every robot operation of the service over REST. Each call names its `Actor` (from the
session); the service's policy decides (the lease, check-before-upload, the instructor's
gate: `melfa.service.policy`), the service audits and answers only after the controller
did. Its refusals map to 4xx in the one error shape (423 ``lease-required``, 409
``simulation-required``, 422 ``program-has-errors``, 409 ``controller-refused`` with the
controller's number, 503 ``link-down``...)."""

from __future__ import annotations

import time
from collections.abc import Awaitable, Callable
from typing import Annotated, TypeVar

from fastapi import APIRouter, Query, Request

from melfa.lang.plan import UploadPlan, plan_upload
from melfa.lang.points import PointKind
from melfa.lang.points_read import parse_points
from melfa.protocol import JOINT_NAMES, POSE_NAMES
from melfa.robot import ControllerError
from melfa.service import Actor, InvalidArgument, ServoPolicy
from melfa.service.policy import plan_refusal
from melfa.service.slot import LoadOrigin, Slot
from melfa.vocab.commands import Command
from melfa.web.context import WebContext
from melfa.web.convert import state_out, workspace_info
from melfa.web.deps import ContextDep, SessionDep, StopSessionDep, actor_of, peer_of
from melfa.web.errors import ERROR_RESPONSES, ApiError, from_refusal, from_robot
from melfa.web.logs import robot_log
from melfa.web.models import (
    ExecIn,
    HandIn,
    HandOut,
    JogStepIn,
    MoveIn,
    Ok,
    OverrideIn,
    OverrideOut,
    RunIn,
    ServoIn,
    SlotMatchIn,
    SlotMatchOut,
    SourceIn,
    StateOut,
    UploadOut,
    ValuesOut,
)
from melfa.web.routes.workspaces import default_workspace, open_workspace
from melfa.web.target_deps import TARGET_HELP, DriveDep, find_target
from melfa.web.targets import LAB

router = APIRouter(prefix="/api/robot", tags=["robot"], responses=ERROR_RESPONSES)

T = TypeVar("T")


async def operate(actor: Actor, name: Command | str, call: Callable[[], Awaitable[T]]) -> T:
    """Run one service call with a log line either way. Its errors reach the one error
    shape (`melfa.web.errors`): the service's `InvalidArgument` is the only 422; anything
    unexpected is a 500 with a log line, never "your input is invalid"."""
    started = time.perf_counter()
    outcome = "ok"
    name = str(name)
    try:
        return await call()
    except InvalidArgument as exc:
        outcome = f"refused: {exc}"
        raise
    except Exception as exc:
        outcome = f"failed: {type(exc).__name__}: {exc}"
        raise
    finally:
        robot_log.info(
            "robot %s by %s: %s",
            name,
            actor.user,
            outcome,
            extra={
                "fields": {
                    "operation": name,
                    "user": actor.user,
                    "session": actor.session_id,
                    "outcome": outcome,
                    "ms": round((time.perf_counter() - started) * 1000, 2),
                }
            },
        )


async def sources(
    context: WebContext, session: SessionDep, body: SourceIn
) -> tuple[str | None, str | None, LoadOrigin]:
    """Program and points from the body, the rest from the workspace; where they came
    from (the workspace named by ``workspace_id``, else the default one when it gave
    text; nothing known when the body gave both)."""
    program, points = body.program, body.points
    origin = LoadOrigin()
    if program is None or points is None or body.workspace_id is not None:
        user = session.user
        if body.workspace_id is not None:
            ws = await open_workspace(context, user, body.workspace_id)
        else:
            ws = await default_workspace(context, user)
        origin = LoadOrigin(ws.id, workspace_info(ws).name)
        if program is None or points is None:
            state = await context.db(context.store.workspaces.state, ws.id)
            program = state.program if program is None else program
            points = state.points if points is None else points
    return program, points, origin


async def planned(context: WebContext, program: str | None, points: str | None) -> UploadPlan:
    """`melfa.lang.plan.plan_upload` (the one home of upload planning), in the loads' pool."""
    return await context.load(plan_upload, program, points)


def checked_program(plan: UploadPlan, check: bool) -> None:
    """Pre-flight and the debugger: a program with errors is refused as a load would be
    (`melfa.service.policy.plan_refusal`, the service's check-before-upload)."""
    if not check:
        return
    refused = plan_refusal(plan)
    if refused is not None:
        raise from_refusal(refused)


def _upload_out(report: object, loaded: UploadPlan | Slot | None = None) -> UploadOut:
    """The reply of a load: what was sent, and what the slot holds now (``loaded``: the
    plan of a program, with or without its points; the slot after points onto it)."""
    out = UploadOut.model_validate(report, from_attributes=True)
    if loaded is not None:
        # The controller reports step numbers; the IDE shows the student's own lines.
        out.step_lines = dict(loaded.step_lines)
        out.fingerprint = loaded.fingerprint
    return out


@router.post("/project", response_model=UploadOut, summary="Load program and points")
async def load_project(
    body: SourceIn, session: SessionDep, drive: DriveDep, context: ContextDep
) -> UploadOut:
    """Program and points into the controller in one session (from the body, else the
    workspace). The service's policy refuses a program with errors before anything is
    sent, and on the lab robot with the instructor's gate one that has not passed
    pre-flight."""
    actor = drive.actor
    program, points, origin = await sources(context, session, body)
    assert program is not None and points is not None
    plan = await planned(context, program, points)
    service = drive.service
    report = await operate(
        actor, Command.LOAD_PROJECT, lambda: service.load_project(actor, plan, origin)
    )
    return _upload_out(report, plan)


@router.post("/program", response_model=UploadOut, summary="Upload the program only")
async def upload_program(
    body: SourceIn, session: SessionDep, drive: DriveDep, context: ContextDep
) -> UploadOut:
    """The program alone (its positions cleared)."""
    actor = drive.actor
    program, _, origin = await sources(context, session, body)
    assert program is not None
    plan = await planned(context, program, None)
    service = drive.service
    report = await operate(
        actor, Command.UPLOAD_PROGRAM, lambda: service.upload_program(actor, plan, origin)
    )
    return _upload_out(report, plan)


@router.post("/points", response_model=UploadOut, summary="Upload the points only")
async def upload_points(
    body: SourceIn, session: SessionDep, drive: DriveDep, context: ContextDep
) -> UploadOut:
    """The points alone (from the body, else the workspace), added to the program the slot
    holds as the controller keeps them: the positions they name replaced, the others kept.
    The reply's ``fingerprint`` and ``step_lines`` are what the slot holds then, the program
    with both (the state's ``slot``); null when that program is not known."""
    actor = drive.actor
    _, points, _ = await sources(context, session, body)
    assert points is not None
    plan = await planned(context, None, points)
    if plan.blocker is None and not plan.items:
        raise ApiError(422, "no-points", "there are no points to upload")
    service = drive.service
    made: list[Slot | None] = []
    report = await operate(
        actor, Command.UPLOAD_POINTS, lambda: service.upload_points(actor, plan, made.append)
    )
    return _upload_out(report, made[-1] if made else None)


@router.post("/slot/match", response_model=SlotMatchOut, summary="Is this text in the slot?")
async def slot_match(body: SlotMatchIn, drive: DriveDep, context: ContextDep) -> SlotMatchOut:
    """Whether the program and points given are the ones in the controller's slot, and if
    so its step -> line map: a page that did not load them itself (the queue's claim, a
    second tab, signing in again) still marks the running line and says the program is
    the editor's. The same means what the controller would hold (`Slot.holds`): the same
    steps in their order, the same positions in any order; the fingerprint returned is the
    slot's, the one a run names. Reads nothing but the state and sends nothing to the
    robot."""
    slot = drive.service.state.slot
    if slot is None:
        return SlotMatchOut(same=False, fingerprint=None, step_lines=None)
    plan = await planned(context, body.program, body.points)
    if not slot.holds(plan):
        return SlotMatchOut(same=False, fingerprint=None, step_lines=None)
    return SlotMatchOut(same=True, fingerprint=slot.fingerprint, step_lines=dict(slot.step_lines))


@router.delete("/program", response_model=Ok, summary="Delete the program")
async def delete_program(drive: DriveDep) -> Ok:
    actor = drive.actor
    await operate(actor, Command.DELETE, lambda: drive.service.delete(actor))
    return Ok()


def servo_policy(servo_on: bool) -> ServoPolicy:
    """A request's ``servo_on`` as the service's rule: the operator's explicit wish to
    move switches the servo on; without it a move with the servo off is refused."""
    return ServoPolicy.TURN_ON if servo_on else ServoPolicy.ASK


@router.post("/run", response_model=Ok, summary="Run the program")
async def run(drive: DriveDep, body: RunIn | None = None) -> Ok:
    actor = drive.actor
    policy = servo_policy(body.servo_on if body is not None else False)
    expect = body.expect if body is not None else None
    await operate(actor, Command.RUN, lambda: drive.service.run(actor, servo=policy, expect=expect))
    return Ok()


@router.post("/stop", response_model=Ok, summary="Stop everything (anyone)")
async def stop(
    request: Request,
    session: StopSessionDep,
    context: ContextDep,
    target: Annotated[str, Query(description=TARGET_HELP)] = LAB,
) -> Ok:
    """Overtakes every queued command; allowed to every signed-in user. Its own path, as
    direct as the WebSocket's: the session comes from memory when this server confirmed it
    recently (else it is read in a pool of its own), and the STOP goes out from the
    service's stop thread, so logins, checks and other requests never delay it."""
    chosen = await find_target(context.targets, session.user.username, target)
    actor = chosen.actor(actor_of(session, peer_of(request)))
    await operate(actor, Command.STOP, lambda: chosen.stop(actor))
    return Ok()


@router.post("/reset-program", response_model=Ok, summary="Back to the first line")
async def reset_program(drive: DriveDep) -> Ok:
    actor = drive.actor
    await operate(actor, Command.RESET_PROGRAM, lambda: drive.service.reset_program(actor))
    return Ok()


@router.post("/reset-alarm", response_model=Ok, summary="Reset the alarm")
async def reset_alarm(drive: DriveDep) -> Ok:
    actor = drive.actor
    await operate(actor, Command.RESET_ALARM, lambda: drive.service.reset_alarm(actor))
    return Ok()


@router.post("/exec", response_model=Ok, summary="Execute one statement")
async def exec_statement(body: ExecIn, drive: DriveDep) -> Ok:
    actor = drive.actor
    if any(c in body.statement for c in "\r\n"):
        raise ApiError(422, "invalid-value", "one statement only: no line breaks")
    try:
        await operate(actor, Command.EXEC, lambda: drive.service.exec(actor, body.statement))
    except ControllerError as exc:
        # The student's own statement may be named (never a request melfa built).
        error = from_robot(exc)
        assert error is not None
        error.message = f"{body.statement.strip()}: {error.message}"
        raise error from None
    return Ok()


@router.post("/hand", response_model=HandOut, summary="Open, close or toggle a hand")
async def hand(body: HandIn, drive: DriveDep) -> HandOut:
    actor = drive.actor
    service = drive.service
    if body.action == "toggle":
        is_open = await operate(actor, Command.HAND, lambda: service.hand_toggle(actor, body.hand))
    else:
        is_open = body.action == "open"
        await operate(actor, Command.HAND, lambda: service.hand(actor, is_open, body.hand))
    return HandOut(hand=body.hand, open=is_open)


@router.post("/move", response_model=Ok, summary="Move to a point or a pose")
async def move(body: MoveIn, session: SessionDep, drive: DriveDep, context: ContextDep) -> Ok:
    """``point``: a name from the workspace's points (its values are sent, so what moves
    is what the student sees); ``pose``: X, Y, Z, A, B, C; ``joints``: J1…J6."""
    actor = drive.actor
    given = [x for x in (body.point, body.pose, body.joints) if x is not None]
    if len(given) != 1:
        raise ApiError(422, "invalid-value", "give exactly one of point, pose or joints")
    service = drive.service
    flags = (body.flags[0], body.flags[1])
    policy = servo_policy(body.servo_on)
    if body.point is not None:
        source = SourceIn(
            program="", points=body.points, workspace_id=body.workspace_id, check=False
        )
        _, points, _ = await sources(context, session, source)
        point = parse_points(points or "").get(body.point.strip())
        if point is None:
            raise ApiError(
                404,
                "unknown-point",
                f"no point {body.point!r} in the workspace's points",
                where={"field": "point"},
            )
        values = point.values[:6]
        if any(v is None for v in values):
            raise ApiError(422, "invalid-value", f"point {point.name} has omitted elements")
        target = [float(v) for v in values if v is not None]
        joints = point.kind is PointKind.JNT
        if not joints:
            flags = (point.fl1 or 0, point.fl2 or 0)
        await operate(
            actor,
            Command.MOVE_TO,
            lambda: service.move_to(
                actor,
                target,
                linear=body.linear,
                joints=joints,
                flags=flags,
                servo=policy,
                label=point.name,
            ),
        )
        return Ok()
    values6 = body.pose if body.pose is not None else body.joints
    assert values6 is not None
    await operate(
        actor,
        Command.MOVE_TO,
        lambda: service.move_to(
            actor,
            values6,
            linear=body.linear,
            joints=body.joints is not None,
            flags=flags,
            servo=policy,
        ),
    )
    return Ok()


@router.post("/servo", response_model=Ok, summary="Servo on or off")
async def servo(body: ServoIn, drive: DriveDep) -> Ok:
    actor = drive.actor
    await operate(actor, Command.SERVO, lambda: drive.service.servo(actor, body.on))
    return Ok()


@router.post("/override", response_model=OverrideOut, summary="Set the speed override")
async def override(body: OverrideIn, drive: DriveDep) -> OverrideOut:
    actor = drive.actor
    value = await operate(
        actor, Command.OVERRIDE, lambda: drive.service.override(actor, body.percent)
    )
    return OverrideOut(percent=value)


@router.post("/jog-step", response_model=Ok, summary="One jog increment")
async def jog_step(body: JogStepIn, drive: DriveDep) -> Ok:
    """For hold-to-move use the WebSocket (``jog_start`` / ``jog_heartbeat``)."""
    actor = drive.actor
    service = drive.service
    await operate(
        actor,
        Command.JOG_STEP,
        lambda: service.jog_step(
            actor, body.frame, body.axis, body.direction, servo=servo_policy(body.servo_on)
        ),
    )
    return Ok()


@router.get("/state", response_model=StateOut, summary="Latest state (no round trip)")
async def get_state(drive: DriveDep) -> StateOut:
    """The latest snapshot; reading it keeps the service polling at full rate for a while,
    so a client that polls this endpoint sees fresh state (its ``at`` says how fresh)."""
    return state_out(drive.service.want_state())


@router.get("/joints", response_model=ValuesOut, summary="Read the joints now")
async def read_joints(drive: DriveDep) -> ValuesOut:
    actor = drive.actor
    values = await operate(actor, Command.READ_JOINTS, lambda: drive.service.read_joints(actor))
    return ValuesOut(names=list(JOINT_NAMES)[: len(values)], values=list(values))


@router.get("/pose", response_model=ValuesOut, summary="Read the pose now")
async def read_pose(drive: DriveDep) -> ValuesOut:
    actor = drive.actor
    values = await operate(actor, Command.READ_POSE, lambda: drive.service.read_pose(actor))
    return ValuesOut(names=list(POSE_NAMES)[: len(values)], values=list(values))


__all__ = ["operate", "router", "servo_policy"]
