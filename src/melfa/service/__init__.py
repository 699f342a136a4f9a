"""melfa.service: the long-running owner of one robot connection (the thesis's Execute Node).

- `RobotService`: priority scheduling (stop > jog > commands > polling) over one worker
  thread, state streaming to any number of subscribers, dead-man jog on client heartbeats,
  operator lease, audit and progress events, reconnects.
- `ThesisMessages`: the thesis's string control messages (appendix 9.1) driving the service.
- Values and events: `Actor`, `Role`, `StateSnapshot`, `LinkStatus`, the event dataclasses.

What it does not do: HTTP, WebSockets, authentication (the web layer's), persistence (the
store's `AuditSink`), or anything on the wire itself (that is `melfa.robot`).
"""

from melfa.service.audit import AuditSink, MemoryAuditSink
from melfa.service.bus import EventBus, Subscription
from melfa.service.config import ServiceConfig
from melfa.service.errors import (
    Cancelled,
    InvalidArgument,
    JogBusy,
    LeaseRequired,
    LinkDown,
    NoJog,
    NotAllowed,
    Refused,
    ServiceClosed,
    ServiceError,
    ThesisMessageError,
)
from melfa.service.events import (
    SERVICE_ACTOR,
    Actor,
    Alarm,
    AuditEvent,
    CommandResult,
    Event,
    JogChanged,
    JogFrame,
    LeaseChanged,
    LinkStatus,
    LinkStatusChanged,
    Role,
    StateSnapshot,
    ThesisOutput,
    UploadProgress,
    event_to_dict,
)
from melfa.service.jog import JogRequest
from melfa.service.lease import Lease
from melfa.service.policy import Gate, Policy
from melfa.service.service import RobotService
from melfa.service.servo import ServoOff, ServoPolicy
from melfa.service.thesis import ThesisMessages, ThesisState

__all__ = [
    "SERVICE_ACTOR",
    "Actor",
    "Alarm",
    "AuditEvent",
    "AuditSink",
    "Cancelled",
    "CommandResult",
    "Event",
    "EventBus",
    "Gate",
    "InvalidArgument",
    "JogBusy",
    "JogChanged",
    "JogFrame",
    "JogRequest",
    "Lease",
    "LeaseChanged",
    "LeaseRequired",
    "LinkDown",
    "LinkStatus",
    "LinkStatusChanged",
    "MemoryAuditSink",
    "NoJog",
    "NotAllowed",
    "Policy",
    "Refused",
    "RobotService",
    "Role",
    "ServiceClosed",
    "ServiceConfig",
    "ServiceError",
    "ServoOff",
    "ServoPolicy",
    "StateSnapshot",
    "Subscription",
    "ThesisMessageError",
    "ThesisMessages",
    "ThesisOutput",
    "ThesisState",
    "UploadProgress",
    "event_to_dict",
]
