"""Byte transports to the controller: serial (pyserial), TCP, any pyserial URL, in-memory.

What it does: open a line with checked settings (9600 8E2 CR by default, `LinkSettings`),
write bytes, read replies under one monotonic deadline per request, wake or close from another
thread, trace both directions (``MELFA_TRACE=1``), pace bytes like a 9600-baud line.
What it does not do: decide what to send (that is `melfa.robot`) or parse replies beyond
cutting them at CR (that is `melfa.protocol`).
"""

from melfa.link.base import POLL_S, Link
from melfa.link.errors import LinkBusy, LinkCancelled, LinkClosed, LinkError, LinkTimeout
from melfa.link.memory import MemoryLink, Responder
from melfa.link.opener import (
    ROBOT_ENV,
    SIM_SPEC,
    TRACE_ENV,
    default_robot,
    is_sim_spec,
    open_link,
    trace_file_sink,
    wrap_link,
)
from melfa.link.serial_link import SerialLink
from melfa.link.settings import BAUDRATES, DEFAULT_TIMEOUT_S, PARITIES, STOPBITS, LinkSettings
from melfa.link.spec import RobotSpec, RobotSpecError, SpecKind, parse_robot
from melfa.link.tcp import TcpLink, parse_tcp_url
from melfa.link.wrappers import PacedLink, TraceEvent, TraceLink, load_trace, render

__all__ = [
    "BAUDRATES",
    "DEFAULT_TIMEOUT_S",
    "PARITIES",
    "POLL_S",
    "ROBOT_ENV",
    "SIM_SPEC",
    "STOPBITS",
    "TRACE_ENV",
    "Link",
    "LinkBusy",
    "LinkCancelled",
    "LinkClosed",
    "LinkError",
    "LinkSettings",
    "LinkTimeout",
    "MemoryLink",
    "PacedLink",
    "Responder",
    "RobotSpec",
    "RobotSpecError",
    "SerialLink",
    "SpecKind",
    "TcpLink",
    "TraceEvent",
    "TraceLink",
    "default_robot",
    "is_sim_spec",
    "load_trace",
    "open_link",
    "parse_robot",
    "parse_tcp_url",
    "render",
    "trace_file_sink",
    "wrap_link",
]
