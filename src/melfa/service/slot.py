"""What is in the controller's program slot: whose program, loaded when, its fingerprint,
from which workspace, and its step → line map.

The lab robot has one slot, shared by thirty students: after bob loads, alice's *Run* runs
bob's program unless she loads hers. The service notes every load that reached the
controller (`after_load`), so every client is told, through the state (`StateSnapshot.slot`),
whose program would run, and a run can name the program it means (`refusal_to_run`: the
``expect``ed fingerprint, refused when the slot holds another). A run-time error names the
student's own line through the loaded step map (`Slot.line_of`).

A refused load never reached the controller: the slot keeps what it held. A load that
failed on the way leaves the slot unknown (None), as the instructor's gate does; so does a
delete (the slot is empty).

Pure: no I/O; the service supplies the time.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
from collections.abc import Mapping
from dataclasses import dataclass, field

from melfa.lang.plan import UploadPlan, digest
from melfa.service.errors import Refused
from melfa.vocab.commands import Command
from melfa.vocab.refusals import Refusal


@dataclass(frozen=True)
class LoadOrigin:
    """Where a load came from, as the door that loads knows it (the IDE's workspace)."""

    workspace_id: int | None = None
    workspace: str = ""
    """The workspace's name as its owner sees it (``group 3``, ``ann``)."""


@dataclass(frozen=True)
class Slot:
    """The program melfa loaded into the controller's slot."""

    user: str
    """Who loaded it."""
    at: dt.datetime
    """When the load finished (UTC)."""
    fingerprint: str
    """`UploadPlan.fingerprint` of the program and points as sent."""
    workspace_id: int | None = None
    workspace: str = ""
    step_lines: Mapping[int, int] = field(default_factory=dict, compare=False, repr=False)
    """The controller's step number → the line of the loaded text (`UploadPlan.step_lines`)."""

    def line_of(self, step: int | None) -> int | None:
        """The loaded text's line of a controller step (None: not known).

        >>> Slot("ann", dt.datetime(2026, 1, 1), "f", step_lines={10: 1, 20: 3}).line_of(20)
        3
        """
        return None if step is None else self.step_lines.get(step)


def after_load(
    slot: Slot | None,
    user: str,
    command: Command,
    plan: UploadPlan | None,
    ok: bool,
    at: dt.datetime,
    origin: LoadOrigin | None = None,
) -> Slot | None:
    """What the slot holds after ``command`` (admitted, so it reached the worker) ended.

    ``user`` loaded it. A program (with or without its points) replaces the slot; points
    alone keep its program and step map under a new fingerprint; a failed load leaves it
    unknown; a delete empties it. Other commands leave it as it was.
    """
    if command is Command.DELETE:
        return None if ok else slot
    if command not in (Command.LOAD_PROJECT, Command.UPLOAD_PROGRAM, Command.UPLOAD_POINTS):
        return slot
    if not ok or plan is None:
        return None
    origin = origin or LoadOrigin()
    if command is Command.UPLOAD_POINTS:
        if slot is None:
            return None
        return dataclasses.replace(
            slot,
            user=user,
            at=at,
            fingerprint=digest((slot.fingerprint, plan.points_digest)),
        )
    return Slot(
        user=user,
        at=at,
        fingerprint=plan.fingerprint,
        workspace_id=origin.workspace_id,
        workspace=origin.workspace,
        step_lines=dict(plan.step_lines),
    )


def refusal_to_run(slot: Slot | None, expect: str | None) -> Refused | None:
    """A run that names the program it means (``expect``: the fingerprint its client
    showed, or confirmed) is refused when the slot holds another one, or nothing known:
    someone loaded in between. No ``expect``: the run goes (the thesis's doors, the CLI).
    """
    if expect is None or (slot is not None and slot.fingerprint == expect):
        return None
    if slot is None:
        return Refused(Refusal.SLOT_UNKNOWN)
    return Refused(Refusal.SLOT_CHANGED, who=slot.user)


__all__ = ["LoadOrigin", "Slot", "after_load", "refusal_to_run"]
