"""The pairing state machine: in turn, STOP overtakes, nothing shifts silently."""

import pytest

from melfa.protocol import (
    ClientConnection,
    ClientState,
    EditRefused,
    LocalProtocolError,
    Ok,
    Refused,
    RemoteProtocolError,
    Request,
)
from melfa.protocol.commands import fits
from melfa.protocol.connection import Paired, Resynced, Unanswered

JPOSF_ANSWER = b"QoKJ1;1.00;;****,****;100;0.00;00000000\r"


def test_one_request_at_a_time() -> None:
    c = ClientConnection()
    c.send(Request("JPOSF"))
    with pytest.raises(LocalProtocolError, match="'JPOSF' awaits"):
        c.send(Request("PPOSF"))
    c.receive_data(JPOSF_ANSWER)
    event = c.next_event()
    assert isinstance(event, Paired) and event.request == Request("JPOSF")
    assert c.state is ClientState.IDLE
    c.send(Request("PPOSF"))


def test_stop_overtakes_and_replies_pair_in_order() -> None:
    c = ClientConnection()
    c.send(Request("EMDAT10 END", slot=9))
    c.send(Request("STOP"))
    assert c.state is ClientState.AWAITING_REPLY
    c.receive_data(b"QeR4220;1;4\r")
    first = c.next_event()
    c.send(Request("NEW"))  # a STOP in flight does not hold the next request back
    c.receive_data(b"QoK\rQoK\r")
    events = [first, c.next_event(), c.next_event()]
    assert events[0] == Paired(Request("EMDAT10 END", slot=9), EditRefused(4220, 1, 4, False))
    assert events[1] == Paired(Request("STOP"), Ok())
    assert events[2] == Paired(Request("NEW"), Ok())


def test_unsolicited_reply_breaks_until_resynchronised() -> None:
    c = ClientConnection()
    c.receive_data(b"QeR6010\r")
    with pytest.raises(RemoteProtocolError, match="unsolicited"):
        c.next_event()
    assert c.state is ClientState.BROKEN
    with pytest.raises(LocalProtocolError, match="out of step"):
        c.send(Request("STATE"))
    assert c.begin_resync() == b"1;1;PARRLNG\r"
    assert c.state is ClientState.RESYNCING
    c.receive_data(b"QoK\rQeR602000000\rQoKRLNG;1;1\r")  # two late replies, then the fence
    event = c.next_event()
    while event is None:
        event = c.next_event()
    assert event == Resynced((Ok(), Refused(6020, detail="00000")), ())
    assert c.state is ClientState.IDLE
    c.send(Request("STATE"))


def test_a_reply_that_does_not_fit_its_request_is_an_error_never_passed_on() -> None:
    c = ClientConnection()
    c.send(Request("STATE"))
    c.receive_data(b"QoK\r")  # the empty answer of some NEW/EMDAT: not a STATE answer
    with pytest.raises(RemoteProtocolError, match="does not fit the request 'STATE'"):
        c.next_event()
    assert c.state is ClientState.BROKEN


def test_stop_answered_while_the_earlier_request_never_is() -> None:
    c = ClientConnection()
    c.send(Request("JPOSF"))
    c.send(Request("STOP"))
    c.receive_data(b"QoK\r")  # STOP's answer; JPOSF's never comes
    first = c.next_event()
    assert isinstance(first, Unanswered) and first.request == Request("JPOSF")
    assert c.next_event() == Paired(Request("STOP"), Ok())
    assert c.state is ClientState.BROKEN  # JPOSF's answer may still come late


def test_garbage_breaks_and_abandon_breaks() -> None:
    c = ClientConnection()
    c.send(Request("STATE"))
    c.receive_data(b"garbage\r")
    with pytest.raises(RemoteProtocolError):
        c.next_event()
    assert c.state is ClientState.BROKEN
    c.reset()
    c.send(Request("STATE"))
    c.abandon("timeout")
    assert c.state is ClientState.BROKEN


def test_resync_gives_up_on_a_line_that_never_answers_the_fence() -> None:
    c = ClientConnection()
    c.send(Request("STATE"))
    c.abandon("timeout")
    c.begin_resync()
    c.receive_data(b"QoK\r" * 40)
    with pytest.raises(RemoteProtocolError, match="without the resynchronising answer"):
        while True:
            c.next_event()


@pytest.mark.parametrize(
    ("command", "reply", "expected"),
    [
        ("NEW", Ok(), True),
        ("NEW", Ok("1"), False),
        ("SAVE", Refused(4170), True),
        ("STATE", EditRefused(4220, 1, 2), False),
        ("EMDAT10 X", EditRefused(4220, 1, 2), True),
        ("PARRLNG", Ok("RLNG;1;1"), True),
        ("PARRLNG", Ok("MEXTL;0.00;6"), False),
        ("PPOSF", Ok("J1;0.00;;****,****;100;0.00;00000000"), False),
        ("JPOSF", Ok("J1;0.00;;****,****;100;0.00;00000000"), True),
        ("ERRORMES602000000", Ok("The Operation is disable"), True),
        ("PDIR<", Ok(), True),
    ],
)
def test_fits(command: str, reply: Ok | Refused | EditRefused, expected: bool) -> None:
    assert fits(command, reply) is expected
