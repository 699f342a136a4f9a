"""The app factory: `create_app(settings)` builds the FastAPI app; its lifespan opens the
store and starts the robot service (unless given ready-made ones, as tests do) and closes
them again: the service stops polling, ends the lease and closes the link."""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import time
from collections.abc import AsyncIterator

from fastapi import FastAPI
from fastapi.routing import APIRoute
from starlette.middleware.gzip import GZipMiddleware

from melfa import __version__
from melfa.link import trace_file_sink
from melfa.ros.rosapi import ParamBudget
from melfa.service import SERVICE_ACTOR, RobotService
from melfa.service.clock import Clock
from melfa.store import Store
from melfa.store.robot_settings import SavedSetting
from melfa.vocab.robot_log import simulator_of
from melfa.web import errors
from melfa.web.audit_sink import ServiceAuditSink
from melfa.web.coedit import CoeditHub
from melfa.web.config import SESSION_COOKIE, WebSettings
from melfa.web.context import WebContext
from melfa.web.deps import find_session
from melfa.web.desk_settings import DeskSettings, StartOptions
from melfa.web.guard import SocketGuard
from melfa.web.known_sessions import KnownSessions
from melfa.web.limits import Shield, csp_for
from melfa.web.logs import RequestLog
from melfa.web.pools import Pools
from melfa.web.preflight import Preflight as PreflightState
from melfa.web.preflight_passes import load_passes
from melfa.web.queues import make_keeper
from melfa.web.recorded_runs import RunKeeper
from melfa.web.rosbridge_app import rosbridge_routes
from melfa.web.routes import (
    assignments,
    audit,
    check,
    coedit,
    debug,
    desk,
    health,
    lease,
    model,
    pages,
    preflight,
    queue,
    robot,
    runs,
    session,
    targets,
    tokens,
    users,
    vocab,
    workspaces,
)
from melfa.web.routes.pages import STATIC
from melfa.web.static_files import CachedStaticFiles
from melfa.web.targets import LAB
from melfa.web.targets import Targets as TargetRegistry
from melfa.web.ws import router as ws_router

TAGS = [
    {"name": "session", "description": "Sign in and out."},
    {"name": "workspaces", "description": "Program and points, saved with every revision."},
    {"name": "check", "description": "Diagnostics and step numbering."},
    {"name": "robot", "description": "Robot operations (lease, audit)."},
    {"name": "targets", "description": "Which robot: the lab's, or your own simulator."},
    {"name": "debug", "description": "The debugger on your own simulator."},
    {"name": "preflight", "description": "A simulated run checked before the arm moves."},
    {"name": "queue", "description": "Turns at the shared robot, fair and in order."},
    {"name": "lease", "description": "Who may move the robot."},
    {"name": "runs", "description": "Recorded runs on the lab robot, and their replay."},
    {"name": "desk", "description": "The instructor's desk: the lab robot's live settings."},
    {"name": "audit", "description": "What moved the robot, and who asked."},
    {"name": "users", "description": "Accounts (instructors: students; admins: everyone)."},
    {"name": "tokens", "description": "My personal access tokens (for programs)."},
    {"name": "health", "description": "Is everything up."},
]


def operation_id(route: APIRoute) -> str:
    """Readable OpenAPI ids: ``tag-name`` (``robot-run``, ``workspaces-save_workspace``)."""
    tag = route.tags[0] if route.tags else "default"
    return f"{tag}-{route.name}"


async def _stop_if_moving(service: RobotService) -> None:
    """The server is going away, and every STOP button with it: a program still running or
    an arm still moving is stopped first (the command line's Ctrl-C convention). A socket's
    holder was stopped as the socket closed; this is the run nobody watches (a script's,
    or one left to finish by `WhenHolderLeaves.FINISH`)."""
    state = service.state
    if state.running or state.moving:
        with contextlib.suppress(Exception):  # a link already down: nothing to stop through
            await service.stop(SERVICE_ACTOR)


def create_app(
    settings: WebSettings | None = None,
    *,
    store: Store | None = None,
    service: RobotService | None = None,
    queue_clock: Clock | None = None,
) -> FastAPI:
    """The web app. A given ``store`` / ``service`` is used as is and left open (the
    caller owns it; a given service must already be started); otherwise the lifespan
    opens ``settings.data_dir`` and starts a service for ``settings.robot``. The lab's
    queue runs on ``queue_clock`` (the wall clock by default; a test's `FakeClock`)."""
    config = settings or WebSettings()

    @contextlib.asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        own_store = store is None
        the_store = store if store is not None else Store.open_dir(config.data_dir)
        the_service = service
        try:
            if the_service is None:
                the_service = RobotService.from_spec(
                    config.robot,
                    trace_sink=trace_file_sink(config.robot_trace) if config.robot_trace else None,
                    config=dataclasses.replace(
                        config.service_config,
                        require_simulation=config.require_simulation,
                        lab_networks=config.lab_networks,
                    ),
                    audit=ServiceAuditSink(the_store.audit),
                )
                await the_service.start()
            registry = TargetRegistry(
                the_service,
                idle_s=config.private_idle_s,
                audit=lambda user: ServiceAuditSink(the_store.audit, simulator_of(user)),
            )
            limits = config.limits
            context = WebContext(
                config,
                the_store,
                the_service,
                registry,
                PreflightState(config.data_dir, the_store.audit),
                pools=Pools(config.pools),
                guard=SocketGuard(
                    limits.max_sockets_per_user,
                    limits.max_sockets,
                    limits.max_sockets_signing_in,
                    known=KnownSessions(limits.socket_recheck_s, limits.stop_session_memory_s),
                ),
                rosapi_params=ParamBudget(
                    limits.rosapi_param_chars, limits.rosapi_param_chars_total
                ),
            )

            async def save(target: str, name: str, value: object, by: str) -> SavedSetting:
                return await context.db(the_store.robot_settings.save, target, name, value, by)

            if the_service.policy.gate is not None:  # a pass counts in the cell as it is
                the_service.policy.gate.cell = lambda: context.preflight.version
            await load_passes(context)  # what passed pre-flight: the store's, kept
            # What staff chose on the desk before a restart, on the start-up options' floor
            # (a service given by the caller brings its own: its gate, its networks).
            policy = the_service.policy
            options = StartOptions(
                config.require_simulation or policy.simulation_required,
                config.lab_networks or (policy.lab.networks if policy.lab is not None else ()),
            )
            context.desk = DeskSettings(
                the_store.robot_settings, save, policy, LAB, options
            ).start()
            turns = make_keeper(
                LAB,
                the_service,
                the_store,
                context.guard,
                config.queue,
                queue_clock or Clock(time.time),
            )
            context.queues[LAB] = await turns.start()
            context.coedit = CoeditHub(
                config.coedit,
                context.db,
                the_store.workspaces.live_doc,
                the_store.workspaces.save_live,
            )
            app.state.web = context
            keeper: RunKeeper | None = None
            if the_service.recorder is None:  # every run on the lab robot is recorded
                keeper = RunKeeper(context, LAB)
                the_service.record_runs(keeper)
            reaper = asyncio.create_task(_reap(registry), name="melfa-private-reaper")
            sweeper = asyncio.create_task(_sweep(context), name="melfa-socket-sweeper")
            try:
                yield
            finally:
                for task in (reaper, sweeper):
                    task.cancel()
                    with contextlib.suppress(asyncio.CancelledError):
                        await task
                for queue in context.queues.values():
                    await queue.close()
                await context.coedit.close()
                await registry.close()
                if keeper is not None:
                    the_service.stop_recording()  # a run under way ends with the server
                    await keeper.drain()
                context.pools.shutdown()
        finally:
            if service is None and the_service is not None:
                await _stop_if_moving(the_service)
                await the_service.close()
            if own_store:
                the_store.close()

    app = FastAPI(
        title="melfa",
        version=__version__,
        description="Program and drive a Mitsubishi RV-6S: accounts, workspaces, checking, "
        "robot operations and live state. Errors share one shape (docs/api.md).",
        openapi_tags=TAGS,
        generate_unique_id_function=operation_id,
        docs_url=None,
        redoc_url=None,
        lifespan=lifespan,
    )
    errors.install(app)
    app.add_middleware(RequestLog)
    app.add_middleware(GZipMiddleware, minimum_size=1024)  # the IDE: < 1 MB on first load
    for router in (
        session.router,
        workspaces.router,
        assignments.router,
        check.router,
        robot.router,
        targets.router,
        debug.router,
        preflight.router,
        runs.router,
        queue.router,
        lease.router,
        audit.router,
        audit.mine,
        users.router,
        desk.router,
        tokens.router,
        health.router,
    ):
        app.include_router(router)
    app.include_router(session.pages)
    app.include_router(audit.pages)
    app.include_router(desk.pages)
    app.include_router(assignments.pages)
    app.include_router(pages.router)
    app.include_router(model.router)
    app.include_router(vocab.router)
    app.include_router(ws_router)
    app.include_router(coedit.router)
    app.include_router(rosbridge_routes())
    app.mount("/static", CachedStaticFiles(directory=STATIC), name="static")
    app.add_middleware(
        Shield,
        limits=config.limits,
        allowed_hosts=config.allowed_hosts,
        allowed_origins=config.allowed_origins,
        csp=csp_for(STATIC / "index.html"),
        session_cookie=SESSION_COOKIE,
    )
    return app


async def _sweep(context: WebContext) -> None:
    """Re-read the session of every open socket now and then: revocations made by another
    process (`melfa users`) and idle expiry close them too."""
    while True:
        await asyncio.sleep(context.settings.limits.socket_recheck_s)
        with contextlib.suppress(Exception):
            await context.guard.sweep(lambda token: find_session(context, token))


__all__ = ["create_app", "operation_id"]


async def _reap(targets: TargetRegistry) -> None:
    """Free idle private simulators, checking a few times per idle period."""
    while True:
        await asyncio.sleep(min(60.0, targets.idle_s / 4))
        await targets.reap()
