"""`open_link(spec)`: one opener for every transport a ``--robot`` spec can name.

=========================  ==================================================================
spec                       link
=========================  ==================================================================
``sim``                    not here: the in-process virtual controller is a layer above the
                           link (`melfa.robot.open_robot_link` opens every form, ``sim`` too)
``tcp://host:port``        `TcpLink` (Ethernet controller, or ``melfa sim --tcp``)
``socket://``, ``loop://``, any other pyserial URL (``rfc2217://``, ``spy://``…): `SerialLink`
``/dev/ttyUSB0``, ``COM3``  a serial device: `SerialLink` at the settings (9600 8E2 default)
=========================  ==================================================================

Tracing: ``trace=True``, or ``MELFA_TRACE=1`` in the environment, wraps the link in a
`TraceLink` printing both directions to stderr.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

from melfa.link.base import Link
from melfa.link.errors import LinkError
from melfa.link.serial_link import SerialLink
from melfa.link.settings import LinkSettings
from melfa.link.spec import ROBOT_ENV, SIM_SPEC, RobotSpecError, SpecKind, parse_robot
from melfa.link.tcp import TcpLink
from melfa.link.wrappers import PacedLink, TraceLink

TRACE_ENV = "MELFA_TRACE"
__all__ = [
    "ROBOT_ENV",
    "SIM_SPEC",
    "TRACE_ENV",
    "default_robot",
    "is_sim_spec",
    "open_link",
    "trace_file_sink",
    "wrap_link",
]


def trace_requested() -> bool:
    """True when ``MELFA_TRACE`` is set to something other than 0/false/no/empty."""
    return os.environ.get(TRACE_ENV, "").strip().lower() not in ("", "0", "false", "no")


def open_link(
    spec: str,
    settings: LinkSettings | None = None,
    *,
    trace: bool | None = None,
    trace_sink: Callable[[str], None] | None = None,
    pace: bool = False,
) -> Link:
    """Open the link ``spec`` names; `LinkError` with a clear message when it cannot."""
    settings = settings or LinkSettings()
    try:
        parsed = parse_robot(spec)
    except RobotSpecError as exc:
        raise LinkError(str(exc)) from None
    link: Link
    if parsed.is_sim:
        raise LinkError(
            "'sim' is the in-process virtual controller: open it with "
            "melfa.robot.open_robot_link (melfa.link opens real transports only)"
        )
    if parsed.kind is SpecKind.TCP:
        link = TcpLink(spec, settings)
    elif parsed.kind is SpecKind.URL:
        link = SerialLink(spec, settings)
    else:
        if not Path(spec).exists() and not spec.upper().startswith("COM"):
            raise LinkError(
                f"no serial device {spec}: is the USB-serial adapter plugged in? "
                "(try `ls /dev/serial/by-id/`), or use tcp://host:port or sim"
            )
        link = SerialLink(spec, settings)
    return wrap_link(link, trace=trace, trace_sink=trace_sink, pace=pace)


def is_sim_spec(spec: str) -> bool:
    """``sim`` (or ``sim:…``): the in-process virtual controller."""
    try:
        return parse_robot(spec).is_sim
    except RobotSpecError:
        return False


def wrap_link(
    link: Link,
    *,
    trace: bool | None = None,
    trace_sink: Callable[[str], None] | None = None,
    pace: bool = False,
) -> Link:
    """Add line pacing and, when asked (or ``MELFA_TRACE``), a trace of both directions."""
    if pace:
        link = PacedLink(link)
    if trace if trace is not None else trace_requested():
        link = TraceLink(link, trace_sink)
    return link


def trace_file_sink(path: Path) -> Callable[[str], None]:
    """A `TraceLink` sink appending each line to ``path`` (flushed, so a crash keeps it)."""
    handle = path.open("a", encoding="utf-8")

    def write(line: str) -> None:
        handle.write(line + "\n")
        handle.flush()

    return write


def default_robot() -> str:
    """``$MELFA_ROBOT`` or ``sim`` (`RobotSpecError` if ``$MELFA_ROBOT`` is malformed)."""
    return parse_robot(None).text
