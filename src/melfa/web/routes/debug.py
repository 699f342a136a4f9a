"""`/api/debug`: the debugger on the caller's own simulator (never the lab robot).

One debug session per user: `POST /api/debug` loads the program (from the body, else the
workspace) with its breakpoints; the commands answer with the new status at once, and the
socket of "My simulator" (`/api/ws?target=mine`) streams ``debug`` messages while the
program runs and at every stop. Requests the engine cannot do are 422 ``debug-refused``
with its plain words (no such line, nothing to finish…)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TypeVar

from fastapi import APIRouter

from melfa.service.debugging import DebugSession
from melfa.sim.debug.engine import DebugError, Debugger, Speed
from melfa.sim.interp.start import RunStart, checked_joints, joints_of_pose
from melfa.vocab.start import StartPlace, StartServo
from melfa.web.context import WebContext
from melfa.web.debug_models import (
    BreakpointsIn,
    DebugCommand,
    DebugOut,
    DebugStartIn,
    EvaluateIn,
    EvaluateOut,
    InputIn,
    RunToIn,
    SpeedIn,
    StartIn,
)
from melfa.web.deps import ActorDep, ContextDep, SessionDep
from melfa.web.errors import ERROR_RESPONSES, ApiError
from melfa.web.models import Ok
from melfa.web.routes.assignments import cell_of_workspace
from melfa.web.routes.robot import checked_program, operate, planned, sources
from melfa.web.targets import MINE, Target

router = APIRouter(prefix="/api/debug", tags=["debug"], responses=ERROR_RESPONSES)
T = TypeVar("T")


def refused(exc: DebugError) -> ApiError:
    return ApiError(422, "debug-refused", str(exc))


def _speed(text: str) -> Speed:
    try:
        return Speed.parse(text)
    except DebugError as exc:
        raise ApiError(422, "invalid-value", str(exc), where={"field": "speed"}) from None


async def _mine(context: WebContext, user: str) -> Target:
    return await context.targets.get(user, MINE)


async def _session(context: WebContext, user: str) -> DebugSession:
    target = await _mine(context, user)
    if target.debug is None or target.debug.closed:
        raise ApiError(
            404, "no-debug-session", "nothing is being debugged: start with POST /api/debug"
        )
    return target.debug


def _out(session: DebugSession) -> DebugOut:
    seq, status, variables = session.snapshot()
    return DebugOut(
        session=session.id, seq=seq, status=status, variables=variables, program=session.program
    )


async def _do(session: DebugSession, fn: Callable[[Debugger], T]) -> T:
    try:
        return await session.call(fn)
    except DebugError as exc:
        raise refused(exc) from None


def run_start(start: StartIn) -> RunStart:
    """The debugger's `RunStart` from the IDE's start options; a start the RV-6S cannot
    take is 422 ``invalid-value`` with why ("the start position is out of …")."""
    servo = {StartServo.ON: True, StartServo.OFF: False}.get(start.servo)
    try:
        joints = None
        if start.place is StartPlace.JOINTS and start.joints is not None:
            joints = checked_joints(start.joints)
        elif start.place is StartPlace.POSE and start.pose is not None:
            p = start.pose
            joints = joints_of_pose((p.x, p.y, p.z, p.a, p.b, p.c), p.fl1, p.fl2)
    except ValueError as exc:
        field = "start.joints" if start.place is StartPlace.JOINTS else "start.pose"
        raise ApiError(422, "invalid-value", str(exc), where={"field": field}) from None
    feed = tuple((f.file, f.line) for f in start.feed)
    return RunStart(servo_on=servo, joints=joints, feed=feed, override=start.override)


def _breakpoints(d: Debugger, lines: list[int], labels: list[str]) -> None:
    """Replace every breakpoint (the editor's gutter is the truth)."""
    d.clear_breakpoints()
    for line in lines:
        d.break_line(line)
    for label in labels:
        d.break_label(label)


def _inputs(d: Debugger, inputs: dict[int, int]) -> None:
    for bit, value in inputs.items():
        d.set_input(bit, value)


@router.post("", response_model=DebugOut, summary="Debug a program on your simulator")
async def start(
    body: DebugStartIn, session: SessionDep, actor: ActorDep, context: ContextDep
) -> DebugOut:
    """Loads the program and its points (a program with errors is refused, as for an
    upload), sets the breakpoints and inputs; it does not run yet (``run`` or ``step``).
    Replaces a session already open."""
    program, points, _ = await sources(context, session, body)
    assert program is not None and points is not None
    checked_program(await planned(context, program, points), body.check)
    speed = _speed(body.speed)
    start_as = run_start(body.start)
    target = await _mine(context, session.user.username)
    simulator = target.simulator
    assert simulator is not None
    if target.debug is not None:
        await target.debug.close()
        target.debug = None
    owner = target.actor(actor)
    # An assignment's workspace runs in the assignment's cell (the student's variant).
    cell = await cell_of_workspace(context, session.user, body.workspace_id)

    async def open_session() -> DebugSession:
        try:
            return await DebugSession.open(
                simulator,
                owner,
                program,
                points,
                speed=speed,
                start=start_as,
                cell=cell if cell is not None else context.preflight.cell,
            )
        except DebugError as exc:
            raise refused(exc) from None

    debug = await operate(owner, "debug_start", open_session)
    target.debug = debug
    await _do(debug, lambda d: _breakpoints(d, body.lines, body.labels))
    await _do(debug, lambda d: _inputs(d, body.inputs))
    return _out(debug)


@router.get("", response_model=DebugOut | None, summary="The debugger's state")
async def get_state(session: SessionDep, context: ContextDep) -> DebugOut | None:
    """Where the program is, why it stopped, the variables: what a reloaded IDE shows; null
    when nothing is being debugged (the IDE asks at every load: no session is no error)."""
    target = await _mine(context, session.user.username)
    if target.debug is None or target.debug.closed:
        return None
    return _out(target.debug)


@router.delete("", response_model=Ok, summary="End the debug session")
async def end(session: SessionDep, context: ContextDep) -> Ok:
    target = await _mine(context, session.user.username)
    if target.debug is not None:
        await target.debug.close()
        target.debug = None
    return Ok()


_COMMANDS: dict[DebugCommand, Callable[[Debugger], object]] = {
    DebugCommand.RUN: lambda d: d.run(),
    DebugCommand.CONTINUE: lambda d: d.continue_(),
    DebugCommand.STEP: lambda d: d.step(),
    DebugCommand.STEP_OVER: lambda d: d.step_over(),
    DebugCommand.STEP_OUT: lambda d: d.step_out(),
    DebugCommand.PAUSE: lambda d: d.pause(),
}


@router.post("/command/{command}", response_model=DebugOut, summary="Run, step, pause…")
async def command(command: DebugCommand, session: SessionDep, context: ContextDep) -> DebugOut:
    """``run`` (from the first line), ``continue``, ``step`` (into GOSUB), ``step-over``,
    ``step-out``, ``pause`` (mid-move too). The program moves afterwards, on the server's
    timer; the reply is the status right after the command."""
    debug = await _session(context, session.user.username)
    await _do(debug, _COMMANDS[command])
    return _out(debug)


@router.post("/run-to", response_model=DebugOut, summary="Run to a line (run to cursor)")
async def run_to(body: RunToIn, session: SessionDep, context: ContextDep) -> DebugOut:
    debug = await _session(context, session.user.username)
    await _do(debug, lambda d: d.run_to(body.line))
    return _out(debug)


@router.put("/breakpoints", response_model=DebugOut, summary="Set every breakpoint")
async def set_breakpoints(
    body: BreakpointsIn, session: SessionDep, context: ContextDep
) -> DebugOut:
    """The whole set, as the editor's gutter shows it (lines) plus labels."""
    debug = await _session(context, session.user.username)
    await _do(debug, lambda d: _breakpoints(d, body.lines, body.labels))
    return _out(debug)


@router.post("/input", response_model=DebugOut, summary="Set an input (M_IN)")
async def set_input(body: InputIn, session: SessionDep, context: ContextDep) -> DebugOut:
    """A ``WAIT M_IN(n)=1`` goes on at the next poll."""
    debug = await _session(context, session.user.username)
    await _do(debug, lambda d: d.set_input(body.bit, body.value))
    return _out(debug)


@router.post("/speed", response_model=DebugOut, summary="Real time, ×N or instant")
async def set_speed(body: SpeedIn, session: SessionDep, context: ContextDep) -> DebugOut:
    speed = _speed(body.speed)
    debug = await _session(context, session.user.username)
    await _do(debug, lambda d: d.set_speed(speed))
    return _out(debug)


@router.post("/evaluate", response_model=EvaluateOut, summary="Print an expression")
async def evaluate(body: EvaluateIn, session: SessionDep, context: ContextDep) -> EvaluateOut:
    debug = await _session(context, session.user.username)
    value = await _do(debug, lambda d: d.evaluate(body.expression))
    return EvaluateOut(expression=body.expression, value=value)


__all__ = ["router"]
