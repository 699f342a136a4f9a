"""The lab's networks: the rule (`melfa.service.lab_network`) and the policy that asks it
(`Policy.from_where`, first in `Policy.admit`, and before a lease is taken)."""

from __future__ import annotations

import ipaddress

import pytest

from melfa.service.errors import Refused
from melfa.service.events import Actor, Role
from melfa.service.lab_network import (
    UNKNOWN_PEER,
    LabNetwork,
    NetworkError,
    parse_networks,
    peer_address,
)
from melfa.service.lease import Lease
from melfa.service.policy import Gate, Policy
from melfa.vocab.commands import Command
from melfa.vocab.refusals import Refusal

LAB = parse_networks(["192.168.10.0/24"])
IN_LAB = ipaddress.ip_address("192.168.10.23")
AT_HOME = ipaddress.ip_address("84.12.3.4")


def student(address: str | None) -> Actor:
    where = None if address is None else ipaddress.ip_address(address)
    return Actor("ann", Role.STUDENT, "s1", where)


def test_networks_are_read_as_staff_write_them() -> None:
    assert [str(n) for n in parse_networks(["192.168.10.7/24, 10.1.0.0/16", " ::1 "])] == [
        "192.168.10.0/24",
        "10.1.0.0/16",
        "::1/128",
    ]
    assert parse_networks(["192.168.10.0/24", "192.168.10.0/24"]) == LAB
    with pytest.raises(NetworkError, match=r"'192\.168\.10\.0/33' is not a network.*/24"):
        parse_networks(["192.168.10.0/33"])
    with pytest.raises(NetworkError, match="'lab' is not a network"):
        parse_networks(["lab"])


def test_the_rule() -> None:
    anywhere, lab = LabNetwork(), LabNetwork(LAB)
    assert anywhere.allows(AT_HOME) and anywhere.anywhere
    assert lab.allows(IN_LAB) and not lab.allows(AT_HOME)
    assert lab.allows(ipaddress.ip_address("::ffff:192.168.10.23"))  # a dual-stack socket
    assert not lab.allows(ipaddress.ip_address("2001:db8::1"))
    assert not lab.allows(UNKNOWN_PEER)
    assert lab.allows(None)  # not over the network: the service, the ROS node on the server
    assert peer_address("192.168.10.23") == IN_LAB
    assert peer_address("::ffff:192.168.10.23") == IN_LAB
    assert peer_address("testclient") == UNKNOWN_PEER == peer_address(None)


def test_a_student_outside_the_lab_is_refused_first_staff_and_the_lab_are_not() -> None:
    lab = LabNetwork(LAB)
    policy = Policy(Lease(), Gate(), lab)
    with pytest.raises(Refused) as refused:
        policy.admit(student("84.12.3.4"), Command.RUN)
    assert refused.value.reason is Refusal.OUTSIDE_LAB
    assert str(refused.value) == " ".join(Refusal.OUTSIDE_LAB.words())
    assert policy.lease.holder is None  # refused before the free lease was taken
    with pytest.raises(Refused, match="only from the lab's computers"):
        policy.from_where(student("84.12.3.4"))  # taking control, joining the queue

    policy.admit(Actor("ivy", Role.INSTRUCTOR, "s2", AT_HOME), Command.SERVO)  # staff
    policy.lease.release(Actor("ivy", Role.INSTRUCTOR, "s2"))
    policy.admit(student("192.168.10.23"), Command.RUN)
    assert policy.lease.holds(student(None))

    lab.networks = ()  # switched live on the desk: anywhere again
    policy.admit(student("84.12.3.4"), Command.JOG)


def test_a_private_simulator_has_no_lab_network() -> None:
    policy = Policy(Lease())
    policy.admit(student("84.12.3.4"), Command.LOAD_PROJECT)
