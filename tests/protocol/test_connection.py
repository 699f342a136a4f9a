import pytest

from melfa.protocol import (
    ClientConnection,
    ClientState,
    LocalProtocolError,
    Ok,
    Refused,
    RemoteProtocolError,
    Request,
)


def test_one_request_at_a_time() -> None:
    c = ClientConnection()
    c.send(Request("JPOSF"))
    with pytest.raises(LocalProtocolError, match="'JPOSF' awaits"):
        c.send(Request("PPOSF"))
    c.receive_data(b"QoKJ1;1.00;;****,****;100;0.00;00000000\r")
    pair = c.next_reply()
    assert pair is not None and pair[0] == Request("JPOSF")
    assert c.state is ClientState.IDLE
    c.send(Request("PPOSF"))


def test_stop_overtakes_and_replies_pair_in_order() -> None:
    c = ClientConnection()
    c.send(Request("EMDAT10 END", slot=9))
    c.send(Request("STOP"))
    assert c.state is ClientState.AWAITING_REPLY
    c.receive_data(b"QeR4220;1;4\rQoK\r")
    first, second = c.next_reply(), c.next_reply()
    assert first is not None and first[0].name == "EMDAT"
    assert second == (Request("STOP"), Ok())


def test_unsolicited_reply_breaks_until_reset() -> None:
    c = ClientConnection()
    c.receive_data(b"QeR6010\r")
    with pytest.raises(RemoteProtocolError, match="unsolicited"):
        c.next_reply()
    assert c.state is ClientState.BROKEN
    with pytest.raises(LocalProtocolError, match="broken"):
        c.send(Request("STATE"))
    c.reset()
    c.send(Request("STATE"))
    c.receive_data(b"QeR6010\r")
    assert c.next_reply() == (Request("STATE"), Refused(6010))


def test_garbage_breaks_and_abandon_breaks() -> None:
    c = ClientConnection()
    c.send(Request("STATE"))
    c.receive_data(b"garbage\r")
    with pytest.raises(RemoteProtocolError):
        c.next_reply()
    assert c.state is ClientState.BROKEN
    c.reset()
    c.send(Request("STATE"))
    c.abandon("timeout")
    assert c.state is ClientState.BROKEN
