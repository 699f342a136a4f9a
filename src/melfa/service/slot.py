"""What is in the controller's program slot, the one record of it every part reads: the
program and points as sent, whose they are, loaded when, from which workspace, and the
step → line map.

The lab robot has one slot, shared by thirty students: after bob loads, alice's *Run* runs
bob's program unless she loads hers. The service notes every load that reached the
controller (`after_load`) in the state (`StateSnapshot.slot`), and everything that asks what
the slot holds reads it there:

- every client is told whose program would run (the state), and a run can name the program
  it means (`refusal_to_run`: the ``expect``ed fingerprint, refused when the slot holds
  another);
- the instructor's gate (`melfa.service.policy.Gate`) lets a run, or points onto the loaded
  program, through only when the program and points it would hold passed pre-flight
  (`Slot.program_digest`, `Slot.points_digest`);
- the run recorder (`melfa.service.recording`) says what a recorded run had loaded and
  names the running line through its step map (`Slot.line_of`), as does a run-time error;
- a client asking whether a text is the one in the slot (`/api/robot/slot/match`) asks
  `Slot.holds`: the same program, step for step in its order (the step → line map refers to
  its lines), and the same positions by name in any order. The controller keeps a
  program's steps by step number and its positions as named variables (read back one by
  name, `LISTP<name>`, `VAL<name>;P`; counted in PDIR; names ignore case), each EMDAT
  item replacing the position of its name, as the virtual controller does
  (`melfa.sim.store.EditBuffer.positions`, by upper-case name). So a points file with the
  same points in another order, or points loaded on their own onto the program, hold the
  same positions: the same text for the controller, and here.

A program and its points loaded separately (the thesis's LOAD PROGRAM, then LOAD POINTS)
are the pair they make: the same fingerprint as the two loaded together. Points loaded onto
a program that holds points already are added to them, as the controller does: the
positions they do not name stay, and the slot holds both (a pair no pre-flight of the new
points alone passed). A refused load
never reached the controller: the slot keeps what it held. A load that failed on the way
leaves the slot not known (None), and so do points loaded onto a slot not known (its program
is still not known); a delete empties it (None too: nothing to run).

Pure: no I/O; the service supplies the time.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

from melfa.lang.plan import UploadPlan, digest, fingerprint_of
from melfa.lang.points_read import parse_points
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
    """The program and points melfa loaded into the controller's slot, and whose they are."""

    user: str
    """Who loaded it (the last load: points onto a program name who sent the points)."""
    at: dt.datetime
    """When the load finished (UTC)."""
    program_lines: tuple[str, ...] = field(repr=False)
    """The program's steps as sent (`UploadPlan.program_texts`)."""
    point_lines: tuple[str, ...] = field(default=(), repr=False)
    """The points as sent (`UploadPlan.point_texts`): a program alone holds none (ECLR)."""
    workspace_id: int | None = None
    workspace: str = ""
    """The workspace's name as its owner sees it (``group 3``, ``ann``)."""
    step_lines: Mapping[int, int] = field(default_factory=dict, compare=False, repr=False)
    """The controller's step number → the line of the loaded text (`UploadPlan.step_lines`)."""
    program: str | None = field(default=None, compare=False, repr=False)
    """The student's own text (what the running line refers to)."""

    @cached_property
    def fingerprint(self) -> str:
        """`UploadPlan.fingerprint` of the program and points it holds: what the client is
        shown and a run's ``expect`` names."""
        return fingerprint_of(self.program_lines, self.point_lines)

    @cached_property
    def program_digest(self) -> str:
        """`UploadPlan.program_digest` of the program it holds (the gate's key)."""
        return digest(self.program_lines)

    @cached_property
    def points_digest(self) -> str:
        """`UploadPlan.points_digest` of the points it holds (the gate's key)."""
        return digest(self.point_lines)

    @cached_property
    def positions(self) -> Mapping[str, str]:
        """The positions it holds by the name the controller sees (upper case) -> their
        value as sent (`positions_of`)."""
        return positions_of(self.point_lines)

    def holds(self, plan: UploadPlan) -> bool:
        r"""Whether loading ``plan`` would leave the controller holding what it holds now:
        the same steps in the same order and the same positions by name, in any order.

        >>> from melfa.lang.plan import plan_upload
        >>> at = dt.datetime(2026, 1, 1)
        >>> one = "DEF POS P1=(1,2,3,4,5,6)(7,0)\nDEF POS P2=(6,5,4,3,2,1)(7,0)\n"
        >>> two = "DEF POS p2=(6,5,4,3,2,1)(7,0)\nDEF POS P1=(1,2,3,4,5,6)(7,0)\n"
        >>> plan = plan_upload("MOV P1\nMOV P2\nEND\n", one)
        >>> slot = Slot("ann", at, plan.program_texts, plan.point_texts)
        >>> slot.holds(plan_upload("MOV P1\nMOV P2\nEND\n", two))
        True
        >>> slot.holds(plan_upload("MOV P2\nMOV P1\nEND\n", one))
        False
        """
        return self.program_lines == plan.program_texts and self.positions == positions_of(
            plan.point_texts
        )

    def line_of(self, step: int | None) -> int | None:
        """The loaded text's line of a controller step (None: not known).

        >>> at = dt.datetime(2026, 1, 1)
        >>> Slot("ann", at, ("10 MOV P1", "20 END"), step_lines={10: 1, 20: 3}).line_of(20)
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
    *,
    clears: bool = True,
) -> Slot | None:
    """What the slot holds after ``command`` (admitted, so it reached the worker) ended.

    ``user`` loaded it. A program (with or without its points) replaces the slot, when the
    load ``clears`` the old program first (`RobotSettings.clear_with_eclr`; else old steps
    and positions it does not overwrite stay: not known). Points alone are sent without
    clearing: they are added to the program it holds, replacing the positions they name
    (onto a program not known: still not known). A failed load leaves it not known; a
    delete empties it. Other commands leave it as it was.
    """
    if command is Command.DELETE:
        return None if ok else slot
    if command not in (Command.LOAD_PROJECT, Command.UPLOAD_PROGRAM, Command.UPLOAD_POINTS):
        return slot
    if not ok or plan is None:
        return None
    if command is Command.UPLOAD_POINTS:
        if slot is None:
            return None
        kept = _not_named(slot.point_lines, plan.point_texts)
        return dataclasses.replace(slot, user=user, at=at, point_lines=plan.point_texts + kept)
    if command is Command.UPLOAD_PROGRAM and not clears:
        return None
    origin = origin or LoadOrigin()
    return Slot(
        user=user,
        at=at,
        program_lines=plan.program_texts,
        point_lines=plan.point_texts,
        workspace_id=origin.workspace_id,
        workspace=origin.workspace,
        step_lines=dict(plan.step_lines),
        program=plan.program,
    )


def positions_of(lines: tuple[str, ...]) -> dict[str, str]:
    """Points as sent (``P1=(…)(7,0)``) by the name the controller sees -> their value as
    sent. A line whose name cannot be read is its own key (equal only to itself).

    >>> positions_of(("p1=(1,2,3,4,5,6)(7,0)", "Jsafe=(0,0,90,0,90,0)"))
    {'P1': '(1,2,3,4,5,6)(7,0)', 'JSAFE': '(0,0,90,0,90,0)'}
    """
    keys = {p.line: p.key for p in parse_points("\n".join(lines)).points}
    out: dict[str, str] = {}
    for n, line in enumerate(lines, 1):
        key = keys.get(n)
        name, sign, value = line.partition("=")
        if key is None or not sign or name.strip().upper() != key:
            out[line] = line
        else:
            out[key] = value
    return out


def _not_named(held: tuple[str, ...], sent: tuple[str, ...]) -> tuple[str, ...]:
    """The positions ``held`` (as sent earlier) that the points ``sent`` do not name: the
    controller keeps them. A line whose name cannot be read is kept (never dropped).

    >>> _not_named(("P1=(1,2,3,4,5,6)(7,0)", "P2=(1,2,3,4,5,6)(7,0)"), ("p1=(0,0,0,0,0,0)(7,0)",))
    ('P2=(1,2,3,4,5,6)(7,0)',)
    """
    if not held:
        return ()
    named = {p.key for p in parse_points("\n".join(sent)).points}
    keys = {p.line: p.key for p in parse_points("\n".join(held)).points}
    return tuple(line for n, line in enumerate(held, 1) if keys.get(n) not in named)


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
