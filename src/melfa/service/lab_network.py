"""Where the lab robot may be driven from: the lab's networks (`melfa serve --lab-network`,
switched live on the instructor's desk).

A student at home once loaded onto the lab's arm, with nobody beside it. With the lab's
networks set (``192.168.10.0/24``), whatever drives the shared robot — taking control,
loading, running, jogging, moving, servo, hand, a queue claim — is refused from anywhere
else (`melfa.vocab.refusals.Refusal.OUTSIDE_LAB`); the policy asks `LabNetwork.allows`
(`melfa.service.policy.Policy.from_where`). STOP never asks it, reading the state and a
private simulator never do. None set: anywhere, as before.

Pure: no sockets. The web doors turn a connection's peer into an `Address` with
`peer_address` (behind a reverse proxy named with ``--trusted-proxy``, uvicorn has already
put the client's own address there).
"""

from __future__ import annotations

import ipaddress
from collections.abc import Iterable
from dataclasses import dataclass

Address = ipaddress.IPv4Address | ipaddress.IPv6Address
"""Where a request came from (a connection's peer)."""
Network = ipaddress.IPv4Network | ipaddress.IPv6Network

UNKNOWN_PEER: Address = ipaddress.IPv4Address("0.0.0.0")
"""The unspecified address, for a peer whose address is not known (a Unix socket): inside no
lab network, so a lab-only robot refuses it."""


class NetworkError(ValueError):
    """A network written in a way melfa cannot read; the message says which and how."""


def parse_network(text: str) -> Network:
    """``192.168.10.0/24`` (or one address, ``192.168.10.7``, or IPv6); host bits are
    dropped (``192.168.10.7/24`` is the lab's ``192.168.10.0/24``)."""
    written = text.strip()
    try:
        return ipaddress.ip_network(written, strict=False)
    except ValueError:
        raise NetworkError(
            f"{written or 'an empty entry'!r} is not a network: write an address and its "
            "prefix length, as 192.168.10.0/24"
        ) from None


def parse_networks(texts: Iterable[str]) -> tuple[Network, ...]:
    """Each of ``texts`` (commas also separate), duplicates once, in the order given."""
    found: list[Network] = []
    for text in texts:
        for part in text.split(","):
            if part.strip():
                network = parse_network(part)
                if network not in found:
                    found.append(network)
    return tuple(found)


def within(networks: Iterable[Network], floor: Iterable[Network]) -> tuple[Network, ...]:
    """The part of ``networks`` that lies inside ``floor``, as networks (two networks
    either nest or are apart, so each overlapping pair gives the smaller one), in the order
    of ``networks``, each once. Empty when nothing of it lies inside."""
    bounds = tuple(floor)
    found: list[Network] = []
    for network in networks:
        for bound in bounds:
            if network.version != bound.version:
                continue
            inner = network if network.subnet_of(bound) else None  # type: ignore[arg-type]
            if inner is None and bound.subnet_of(network):  # type: ignore[arg-type]
                inner = bound
            if inner is not None and inner not in found:
                found.append(inner)
    return tuple(found)


def plain(address: Address) -> Address:
    """An IPv4 client of a dual-stack socket (``::ffff:192.168.10.7``) as IPv4."""
    if isinstance(address, ipaddress.IPv6Address) and address.ipv4_mapped is not None:
        return address.ipv4_mapped
    return address


def peer_address(host: str | None) -> Address:
    """A connection's peer host (ASGI's ``client[0]``) as an address; `UNKNOWN_PEER` when
    there is none or it is not an address."""
    if not host:
        return UNKNOWN_PEER
    try:
        return plain(ipaddress.ip_address(host))
    except ValueError:
        return UNKNOWN_PEER


@dataclass
class LabNetwork:
    """The lab's networks; empty: anywhere. `networks` is replaced whole when staff switch
    it (one assignment: every door sees the old list or the new one)."""

    networks: tuple[Network, ...] = ()

    @property
    def anywhere(self) -> bool:
        return not self.networks

    def allows(self, address: Address | None) -> bool:
        """Whether the robot may be driven from ``address`` (None: not over the network —
        the service itself, the queue acting for a claim it admitted, the ROS node on
        the server)."""
        if address is None or not self.networks:
            return True
        where = plain(address)
        return any(where in network for network in self.networks)

    def written(self) -> list[str]:
        """The networks as staff write them (``192.168.10.0/24``)."""
        return [str(network) for network in self.networks]


__all__ = [
    "UNKNOWN_PEER",
    "Address",
    "LabNetwork",
    "Network",
    "NetworkError",
    "parse_network",
    "parse_networks",
    "peer_address",
    "plain",
    "within",
]
