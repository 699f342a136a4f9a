"""Link failures: the line, not the protocol and not the controller."""

from __future__ import annotations


class LinkError(Exception):
    """The transport failed: cannot open, adapter pulled, peer gone, closed."""


class LinkTimeout(LinkError):
    """No (complete) reply before the request's deadline."""


class LinkClosed(LinkError):
    """The link was closed (by us, from any thread) or the peer hung up."""


class LinkCancelled(LinkError):
    """A blocked read was woken by `Link.cancel_read` from another thread."""


class LinkBusy(LinkError):
    """The port is held by another process (another melfa command, a terminal program)."""


BUSY_HINT = (
    "another program holds it (another melfa command, such as a `melfa run --wait` still "
    "running, or `melfa serve`). To stop the robot, press Ctrl-C in that command or STOP in "
    "the IDE; the emergency stop on the pendant always works"
)
"""What to do when the port is held: the one place that says it."""
