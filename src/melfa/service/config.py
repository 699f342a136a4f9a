"""Everything about the service that a lab may want to tune, in one checked object."""

from __future__ import annotations

import enum
from dataclasses import dataclass

from melfa.protocol.jog import JOG_WATCHDOG_S
from melfa.protocol.limits import OVERRIDE_PERCENT, span_text
from melfa.service.lab_network import Network
from melfa.service.servo import ServoPolicy


class WhenHolderLeaves(enum.Enum):
    """What a move or program does when its owner's last connection closes (a jog always
    stops at once: it needs a held key)."""

    STOP = "stop"
    """Stop the arm (the default: nobody is watching the screen that started it)."""
    FINISH = "finish"
    """Let it finish; the owner keeps the lease, shown as disconnected, until it ends."""


@dataclass(frozen=True)
class ServiceConfig:
    """Service options (defaults in brackets are why)."""

    polling: bool = True
    """Poll the controller for state at all (off: only explicit reads; tests of traffic)."""
    poll_floor_s: float = 0.01
    """Shortest pause between two poll requests while someone listens. On a real 9600-baud
    line the round trip (≈125 ms for JPOSF [DERIVED protocol.md §6.1]) is the real limit;
    the floor only keeps an instant in-memory simulator from burning a CPU."""
    idle_poll_s: float = 2.0
    """Pause between poll requests when nobody listens (still notices a dead link)."""
    state_interest_s: float = 10.0
    """How long a `RobotService.want_state` call (a REST state read) counts as a listener."""
    pose_every: int = 3
    """Read PPOSF every n-th cycle; in between the pose is computed from JPOSF with kin's
    forward kinematics and the tool offset learned from the last still PPOSF."""
    state_every: int = 4
    """Read STATE (program, line, servo, run, alarm, override) every n-th cycle."""
    hand_every: int = 12
    """Read HNDSTS every n-th cycle."""
    running_spacing_s: float = 0.1
    """[DOC S1 §3.3.3] ≥ 100 ms between a reply and the next request while a program
    runs; applied to polling only (commands and stop go at once)."""

    jog_watchdog_s: float = JOG_WATCHDOG_S
    """The controller's JOG dead-man [DOC S1 §5.2.59], for the poll budget while jogging."""
    jog_poll_margin_s: float = 0.03
    """While jogging, a poll is only sent if it and the next JOG fit in the watchdog minus
    this margin (round trips are measured), so polling never starves the jog."""
    jog_poll_every_s: float = 0.25
    """While jogging on a line where no poll fits between two JOG renewals, poll anyway
    this often (one short pause of the jog) so the state keeps flowing."""
    jog_heartbeat_timeout_s: float = 0.3
    """A jog whose heartbeats stop for this long is ended by the service (the arm has
    already stopped by itself after the controller watchdog)."""
    jog_override_ceiling: int = 10
    """OP override (%) while jogging: lowered to this before the first JOG/step if higher,
    restored before the next user command that moves the arm [design.md: jog speed capped]."""
    jog_override_step: int = 2
    """An override raised during a jog climbs by at most this many % per JOG renewal
    (never a jump); a lower one applies at once. The ceiling still holds."""
    step_waits_for_motion: bool = False
    """Step jog: also wait in the worker until the step has finished moving."""

    motion_servo: ServoPolicy = ServoPolicy.LEAVE
    """What a moving command does with the servo off when its caller did not say
    (`melfa.service.servo`). The web API always says (``servo_on``: TURN_ON, else ASK);
    the default leaves the controller to refuse, as before."""

    lease_idle_timeout_s: float | None = 600.0
    """End a lease after this long without a command, jog or motion of its holder, however
    it was taken (IDE or REST); None: never (a forgotten script would lock the lab out)."""
    auto_lease: bool = True
    """A moving command from a student/instructor takes a free lease (published like any
    change, and given back if that command fails)."""
    require_simulation: bool = False
    """The instructor's gate (``melfa serve --require-simulation``): the robot loads and
    runs only a program and points that passed pre-flight (`melfa.service.policy.Gate`)."""
    lab_networks: tuple[Network, ...] = ()
    """Where the robot may be driven from (``melfa serve --lab-network``; empty: anywhere):
    `melfa.service.lab_network.LabNetwork`, asked by the policy."""
    when_holder_leaves: WhenHolderLeaves = WhenHolderLeaves.STOP
    """A move or program when its owner's last connection closes (their jog always stops)."""

    reconnect_initial_s: float = 0.2
    reconnect_max_s: float = 5.0
    lost_after_s: float = 10.0
    """Status becomes ``lost`` after reconnecting this long (it keeps trying)."""

    subscriber_maxlen: int = 256
    close_timeout_s: float = 10.0
    """How long `close` waits for the command in flight to finish."""

    def __post_init__(self) -> None:
        for name in ("pose_every", "state_every", "hand_every"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be ≥ 1")
        if self.jog_override_step not in OVERRIDE_PERCENT:
            raise ValueError(f"jog_override_step must be {span_text(OVERRIDE_PERCENT)} %")
        if self.lease_idle_timeout_s is not None and self.lease_idle_timeout_s <= 0:
            raise ValueError("lease_idle_timeout_s must be positive (or None)")
        if self.jog_override_ceiling not in OVERRIDE_PERCENT:
            raise ValueError(f"jog_override_ceiling must be {span_text(OVERRIDE_PERCENT)} %")
        if self.reconnect_initial_s <= 0 or self.reconnect_max_s < self.reconnect_initial_s:
            raise ValueError("reconnect delays must be positive and initial ≤ max")
        if self.jog_heartbeat_timeout_s <= 0 or self.poll_floor_s < 0 or self.idle_poll_s <= 0:
            raise ValueError("times must be positive")


__all__ = ["ServiceConfig", "WhenHolderLeaves"]
