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
