"""`open_robot_link(spec)`: every ``--robot`` form, the virtual controller included.

``sim`` opens an in-process virtual CR2B-574 (`melfa.sim.open_sim_link`); anything else is
a real transport opened by `melfa.link.open_link` (serial device, ``tcp://``, pyserial URL).
The simulator is imported only when asked for, so a lab PC driving the real arm never loads
it; the dependency points down (robot → sim → link), never from link up to sim.
"""

from __future__ import annotations

from collections.abc import Callable

from melfa.link import Link, LinkSettings, is_sim_spec, open_link, wrap_link


def open_robot_link(
    spec: str,
    settings: LinkSettings | None = None,
    *,
    trace: bool | None = None,
    trace_sink: Callable[[str], None] | None = None,
    pace: bool = False,
) -> Link:
    """Open what ``spec`` names; `melfa.link.LinkError` with a clear message if it cannot."""
    if not is_sim_spec(spec):
        return open_link(spec, settings, trace=trace, trace_sink=trace_sink, pace=pace)
    from melfa.sim import open_sim_link  # lazily: the simulator loads for --robot sim only

    link = open_sim_link(settings=settings or LinkSettings())
    return wrap_link(link, trace=trace, trace_sink=trace_sink, pace=pace)
