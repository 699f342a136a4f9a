"""The policy: whether a command may be queued for the robot, decided once, in the service.

Every command that loads, moves or changes the robot (load, run, jog, move to, a single
statement, servo, hand, override, delete, reset) passes `Policy.admit` inside the service
before it is queued, whoever called: REST, the WebSocket, rosbridge, the thesis's control
messages, the ROS 1 node, the desktop client. A refusal is `Refused`: a reason from
`melfa.vocab.refusals.Refusal` with the student's words and the fix, the same from every
door (REST maps the reason to its status and code, rosbridge and the thesis's messages
send the words).

What it holds, in the order it asks:

0. **The lab's networks** (`melfa.service.lab_network.LabNetwork`, on the lab robot with
   ``--lab-network``, switched live on the instructor's desk): from anywhere else a student's
   command is refused (`Refusal.OUTSIDE_LAB`), and so are taking control, joining the queue
   and claiming a turn (`Policy.from_where`, asked by the lease and the queue). Staff
   (instructors and admins) are exempt: they switch the setting from anywhere anyway. STOP
   never passes here; reading the state and a private simulator are never restricted.
1. **Check-before-upload.** A load carries its `melfa.lang.plan.UploadPlan`; a plan with an
   error (the checker's, the points', or one that cannot be sent) is refused, so a program
   with errors never reaches the controller.
2. **The instructor's gate** (`Gate`, on the lab robot with ``--require-simulation``): a
   load is refused unless the same program and points, as sent (`UploadPlan.fingerprint`),
   passed pre-flight (`Gate`: the store's one record of passes, anyone's pass of the same
   text in the same cell; a program alone: with some points), and points alone unless
   they and the program the slot holds did; a run is refused unless what the slot holds
   passed. What the slot holds is the service's one record of it
   (`melfa.service.slot.Slot`, the state's ``slot``, read through `Policy.slot`): the gate
   keeps none of its own. A program and its points loaded
   separately (the thesis's LOAD PROGRAM then LOAD POINTS) count as the pair they make;
   a slot not known (nothing loaded since the service started, a failed load, points onto
   a program not known, a delete) passes nothing. A pass counts only in the version of
   the lab's cell it ran in (`Gate.cell`): after an instructor edits the cell, what passed
   before is refused (`Refusal.CELL_CHANGED`) until it passes pre-flight again.
3. **The operator lease** (`melfa.service.lease.Lease`): only its holder's commands go;
   with ``auto`` a free lease is taken by the first command (the change is returned for
   the service to publish, and given back if the command fails).

4. **The queue's turn** (`Turns`, the lab's `melfa.service.queue_keeper.QueueKeeper`):
   once a turn's time is up nothing new starts (`Refusal.TURN_OVER`), and in attended mode
   a run waits for the supervisor's *Arm ready* (`Policy.attend`). While the queue is
   active the lease itself refuses a free take (`Refusal.QUEUE_ACTIVE`).

5. **The instructor's hold** (`Policy.hold`): staff stopped the robot and hold it; every
   command from anyone but staff is refused (`Refusal.HELD`, naming who holds it) until
   they release it. Staff may reset an alarm without taking the lease (nothing moves).

Entering the queue asks the same policy (`Policy.may_queue`): the plan passes the checker
and, with the gate on, passed pre-flight (its cycle time is kept for the queue's
estimates, `Policy.cycle_time`).

A private simulator has the lighter `Policy` without a gate; its lease has one possible
holder, its owner (every session of theirs is one operator), so it never stands between
them.
"""

from __future__ import annotations

import threading
from collections.abc import Awaitable, Callable, Iterable
from typing import Protocol

from melfa.lang.plan import Part, UploadPlan
from melfa.service.errors import Refused
from melfa.service.events import Actor, Role
from melfa.service.lab_network import LabNetwork
from melfa.service.lease import Lease, LeaseChange
from melfa.service.slot import Slot
from melfa.vocab.commands import Command
from melfa.vocab.refusals import Asked, Refusal

RUNS = frozenset({Command.RUN})
"""Commands that start the loaded program (the gate asks what the slot holds)."""


class Pass(Protocol):
    """A passed pre-flight as the gate reads it (the store's `melfa.store.preflights.Pass`)."""

    @property
    def program_digest(self) -> str: ...
    @property
    def points_digest(self) -> str: ...
    @property
    def cell(self) -> str: ...
    @property
    def cycle_time(self) -> float | None: ...


class Gate:
    """The instructor's gate: which programs and points passed pre-flight, and in which
    version of the lab's cell (`melfa.sim.debug.cell.Cell.digest`). A pass counts only in
    the cell as it is now (`cell`): once an instructor moves a fixture, a program that
    passed around the old one needs a new pre-flight (`Refusal.CELL_CHANGED`); undoing the
    edit makes it count again. What the lab robot holds it reads from the one record of the
    slot (`melfa.service.slot.Slot`).

    **Whose pass counts: anyone's.** The gate asks whether this program and these points,
    as sent, ran without a pre-flight error in the cell as it is; a pass is a fact about
    the text and the cell, not about who pressed Pre-flight, and the arm does the same
    thing whoever loads the same text (partners sharing a workspace, a student loading the
    text a classmate simulated). Counting only one's own pass would add no safety, only
    another simulation of the identical run.

    **One record.** What passed is the store's (`melfa.store.preflights`): the web loads
    every pass into the gate at start (`load`) and tells it of each new one only once it
    is stored (`passed`), so the gate's index is the store's rows, and a decision never
    waits on the disk. Thread-safe (pre-flight records from a worker thread)."""

    def __init__(self, required: bool = False) -> None:
        self.required = required
        self.cell: Callable[[], str] = lambda: ""
        """The version of the cell pre-flight runs in now: the web, which keeps the cell
        (`melfa.web.preflight.Preflight.version`), sets it; without one, one cell ("")."""
        self._lock = threading.Lock()
        self._passed: dict[tuple[str, str], dict[str, float | None]] = {}
        """(program, points) digests -> each cell version they passed in -> cycle time."""

    def passed(self, plan: UploadPlan, cycle_s: float | None = None, cell: str = "") -> None:
        """``plan``'s program and points passed pre-flight (a simulated run without
        errors) in version ``cell`` of the cell, in ``cycle_s`` simulated seconds."""
        self._add(plan.program_digest, plan.points_digest, cell, cycle_s)

    def load(self, passes: Iterable[Pass]) -> None:
        """The passes kept in the store (oldest first), read when the server starts."""
        for found in passes:
            self._add(found.program_digest, found.points_digest, found.cell, found.cycle_time)

    def _add(self, program: str, points: str, cell: str, cycle_s: float | None) -> None:
        with self._lock:
            cells = self._passed.setdefault((program, points), {})
            cells.pop(cell, None)  # the newest pass last (`cycle_time`'s "last known")
            cells[cell] = cycle_s

    def cycle_time(self, plan: UploadPlan) -> float | None:
        """``plan``'s pre-flight cycle time: in the cell as it is now, else the last known."""
        with self._lock:
            cells = self._passed.get((plan.program_digest, plan.points_digest), {})
            now = cells.get(self.cell())
            if now is not None:
                return now
            return next((c for c in reversed(cells.values()) if c is not None), None)

    def refusal(
        self, command: Command, plan: UploadPlan | None, slot: Slot | None
    ) -> Refusal | None:
        """Why the gate holds ``command`` (with its ``plan``) back while the slot holds
        ``slot`` (None: nothing known), or None: it may go. A load of a whole project
        (and a plan entering the queue) needs its pair passed; a program alone, with some
        points; points alone, with the program the slot holds; a run, what the slot holds.
        Passed in an earlier cell only: `Refusal.CELL_CHANGED`."""
        if not self.required:
            return None
        with self._lock:
            wanted = self._wanted(command, plan, slot)
        return None if wanted is None else self._verdict(wanted)

    def pair_refusal(self, program_digest: str, points_digest: str) -> Refusal | None:
        """What a load of this program and points would be told now (None: it goes)."""
        if not self.required:
            return None
        return self._verdict([(program_digest, points_digest)])

    def _verdict(self, wanted: list[tuple[str, str]]) -> Refusal | None:
        """Passed in the cell as it is (None), only in another (`Refusal.CELL_CHANGED`),
        or never (`Refusal.SIMULATION_REQUIRED`)."""
        now = self.cell()
        with self._lock:
            cells = {c for pair in wanted for c in self._passed.get(pair, {})}
        if now in cells:
            return None
        return Refusal.CELL_CHANGED if cells else Refusal.SIMULATION_REQUIRED

    def _wanted(
        self, command: Command, plan: UploadPlan | None, slot: Slot | None
    ) -> list[tuple[str, str]] | None:
        """The (program, points) pairs of which one must have passed (None: not gated)."""
        if command is Command.LOAD_PROJECT and plan is not None:
            return [(plan.program_digest, plan.points_digest)]
        if command is Command.UPLOAD_PROGRAM and plan is not None:
            return [pair for pair in self._passed if pair[0] == plan.program_digest]
        if command is Command.UPLOAD_POINTS and plan is not None:
            return [] if slot is None else [(slot.program_digest, plan.points_digest)]
        if command in RUNS:
            return [] if slot is None else [(slot.program_digest, slot.points_digest)]
        return None


def plan_refusal(plan: UploadPlan) -> Refused | None:
    """Check-before-upload: the refusal of a plan with an error (the program's first, else
    the points'), or None. What cannot be sent at all is among the errors
    (`UploadPlan.blocker` adds its diagnostic)."""
    first = plan.first_error()
    if first is None:
        return None
    part, found = first
    points = part is Part.POINTS
    errors = plan.point_diagnostics if points else plan.diagnostics
    return Refused(
        Refusal.POINTS_HAVE_ERRORS if points else Refusal.PROGRAM_HAS_ERRORS,
        where={"source": part.value, "line": found.line, "column": found.column},
        detail={"diagnostics": [d.to_json() for d in errors if d.is_error]},
        line=found.line,
        message=_sentence(found.message),
    )


def _sentence(text: str) -> str:
    text = text.strip()
    return text if text.endswith((".", "?", "!")) else text + "."


class Turns(Protocol):
    """The queue's say in the policy (the lab's `QueueKeeper`)."""

    def refusal(self, actor: Actor, command: Command) -> Refused | None:
        """Why ``actor``'s ``command`` may not go now (None: it may)."""

    def attend(self, actor: Actor, command: Command) -> Awaitable[None] | None:
        """What the command waits for before it is queued (attended mode), or None."""

    def stopped(self) -> None:
        """Someone pressed STOP (a run waiting for the supervisor is dropped)."""


class Policy:
    """One check for every command before it is queued (see the module doc)."""

    def __init__(
        self,
        lease: Lease,
        gate: Gate | None = None,
        lab: LabNetwork | None = None,
        slot: Callable[[], Slot | None] = lambda: None,
    ) -> None:
        self.lease = lease
        self.gate = gate
        self.slot = slot
        """What the controller's slot holds now (the service's state: the one record)."""
        self.lab = lab
        """The lab's networks (the lab robot's; None: a private simulator, anywhere)."""
        self.turns: Turns | None = None
        """The queue of a shared robot (set by its keeper)."""
        self.held_by: str | None = None
        """Who of the staff holds the robot stopped (`hold`); None: nobody."""

    def hold(self, user: str | None) -> None:
        """``user`` (staff) holds the robot: only staff's commands go until ``hold(None)``."""
        self.held_by = user

    def admit(
        self, actor: Actor, command: Command, plan: UploadPlan | None = None
    ) -> LeaseChange | None:
        """Let ``command`` through or raise `Refused` (nothing queued, nothing changed).
        Returns the lease change when it took a free lease (the service publishes it)."""
        self.from_where(actor)
        if plan is not None:
            refused = plan_refusal(plan)
            if refused is not None:
                raise refused
        staff = actor.role is Role.INSTRUCTOR
        if self.held_by is not None and not staff:
            raise Refused(Refusal.HELD, who=self.held_by)
        gated = None if self.gate is None else self.gate.refusal(command, plan, self.slot())
        if gated is not None:
            raise Refused(gated, asked=Asked.RUN if command in RUNS else Asked.LOAD)
        if staff and command is Command.RESET_ALARM:
            return None  # the staff side resets a student's alarm without taking over
        change = self.lease.check(actor)
        if self.turns is not None:
            refused = self.turns.refusal(actor, command)
            if refused is not None:
                raise refused
        return change

    def from_where(self, actor: Actor) -> None:
        """Whether ``actor`` may drive this robot from where they are (the lab's networks;
        staff anywhere): raises `Refused` (`Refusal.OUTSIDE_LAB`)."""
        lab = self.lab
        if lab is None or actor.role is Role.INSTRUCTOR:
            return
        if not lab.allows(actor.address):
            raise Refused(Refusal.OUTSIDE_LAB)

    def attend(self, actor: Actor, command: Command) -> Awaitable[None] | None:
        """What an admitted command waits for before it is queued (None: nothing)."""
        return None if self.turns is None else self.turns.attend(actor, command)

    def stopped(self) -> None:
        if self.turns is not None:
            self.turns.stopped()

    def queued_refusal(self, program_digest: str, points_digest: str) -> Refusal | None:
        """What the gate would say now to a queued text (its program and points digests)
        at its turn: the queue warns its student at once (None: it would load)."""
        if self.gate is None:
            return None
        return self.gate.pair_refusal(program_digest, points_digest)

    def may_queue(self, plan: UploadPlan) -> None:
        """Whether ``plan`` may enter the queue: no error (the checker's, the points'),
        and with the gate on, the same text passed pre-flight in the cell as it is now.
        Raises `Refused`."""
        refused = plan_refusal(plan)
        if refused is not None:
            raise refused
        gated = None if self.gate is None else self.gate.refusal(Command.LOAD_PROJECT, plan, None)
        if gated is not None:
            raise Refused(gated, asked=Asked.QUEUE)

    def cycle_time(self, plan: UploadPlan) -> float | None:
        """``plan``'s pre-flight cycle time, when it ran."""
        return None if self.gate is None else self.gate.cycle_time(plan)

    @property
    def simulation_required(self) -> bool:
        """Whether the instructor's gate is on."""
        return self.gate is not None and self.gate.required

    def gate_passed(self, plan: UploadPlan, cycle_s: float | None = None, cell: str = "") -> None:
        """``plan`` passed pre-flight in version ``cell`` of the cell (the web's pre-flight
        records it; no gate: nothing)."""
        if self.gate is not None:
            self.gate.passed(plan, cycle_s, cell)


__all__ = ["Gate", "Pass", "Policy", "Turns", "plan_refusal"]
