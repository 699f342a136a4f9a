"""The one record of what passed pre-flight, wired: a pass is kept in the store
(`melfa.store.preflights`) and only then told to the lab service's gate
(`melfa.service.policy.Gate`), and the gate reads every kept pass when the server starts.
So a restart keeps a student's pass, and the gate and the comparison of a real run with its
simulation (`melfa.web.recorded_runs`) read the same fact."""

from __future__ import annotations

from melfa.lang.plan import UploadPlan
from melfa.service.recording_compare import pack, simulated_run
from melfa.sim.debug.preflight import Report
from melfa.store.preflights import NewPass
from melfa.web.context import WebContext
from melfa.web.recorded_runs import patiently


async def load_passes(context: WebContext) -> int:
    """Every kept pass into the lab service's gate (at start); how many there were."""
    gate = context.service.policy.gate
    if gate is None:
        return 0
    passes = await context.db(context.store.preflights.passes)
    gate.load(passes)
    return len(passes)


async def keep_pass(
    context: WebContext, user: str, plan: UploadPlan, report: Report, cell: str
) -> None:
    """``user``'s pre-flight of ``plan`` passed in version ``cell`` of the lab's cell: kept
    (with its path, for later real runs), then the gate opens for the same text in that
    cell, for anyone (`Gate`'s rule). A full pool delays it: the pre-flight passed, so its
    answer must not become a 503."""
    path = [(p.time, p.x, p.y, p.z, p.line) for p in report.path]
    data = await patiently(lambda: context.cpu(pack, simulated_run(path, report.cycle_time)))
    new = NewPass(
        username=user,
        fingerprint=plan.fingerprint,
        program_digest=plan.program_digest,
        points_digest=plan.points_digest,
        cell=cell,
        cycle_time=report.cycle_time,
        path=data,
    )
    await patiently(lambda: context.db(context.store.preflights.record, new))
    context.service.policy.gate_passed(plan, report.cycle_time, cell)
    for queue in context.queues.values():  # a queued text it may pass again
        queue.gate_changed()


__all__ = ["keep_pass", "load_passes"]
