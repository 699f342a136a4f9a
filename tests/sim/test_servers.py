"""The transports: a pyserial client at 9600 8E2 on a fresh pty, TCP, the in-memory link,
and the framing every server shares (split input, garbage, over-long lines)."""

from __future__ import annotations

import socket

import pytest
import serial
from hypothesis import given
from hypothesis import strategies as st

from melfa.link import LinkSettings, SerialLink, TcpLink, parse_tcp_url
from melfa.protocol import Request
from melfa.protocol.messages import Ok, Refused
from melfa.sim import (
    NO_PACING,
    Pacing,
    PtyServer,
    SimConfig,
    TcpServer,
    VirtualController,
    WireSession,
    open_sim_link,
)
from melfa.sim.session import MAX_LINE_BYTES

TIMEOUT_S = 20.0
"""Generous: only a failing test waits this long; a loaded machine must not fail one."""


def _read_reply(port: serial.Serial) -> bytes:
    data = b""
    while not data.endswith(b"\r"):
        chunk = port.read(1)
        assert chunk, f"timeout after {data!r}"
        data += chunk
    return data


def _recv_reply(sock: socket.socket) -> bytes:
    """One whole reply from TCP (a reply may arrive in several segments)."""
    data = b""
    while not data.endswith(b"\r"):
        chunk = sock.recv(4096)
        assert chunk, f"connection closed after {data!r}"
        data += chunk
    return data


def test_pyserial_8e2_client_on_a_fresh_pty(sim_pty_path: str) -> None:
    with serial.Serial(
        sim_pty_path, 9600, bytesize=8, parity="E", stopbits=2, timeout=TIMEOUT_S
    ) as port:
        port.write(b"1;1;OPEN=NARCUSR\r")
        assert _read_reply(port).startswith(b"QoK3F;3F;")
        port.write(b"1;1;CNTLON\r1;1;SRVON\r")  # two requests in one write
        assert _read_reply(port) == b"QoK\r"
        assert _read_reply(port) == b"QoK\r"
        port.write(b"1;1;JPO")  # one request in pieces
        port.flush()
        port.write(b"SF\r")
        assert _read_reply(port).startswith(b"QoKJ1;0.00;J2;0.00;J3;90.00;")


def test_each_port_is_fresh_and_disconnect_ends_the_session() -> None:
    sim = VirtualController(SimConfig(open_required=True))
    with PtyServer(sim) as server:
        first = server.new_port()
        with serial.Serial(first, 9600, parity="E", stopbits=2, timeout=TIMEOUT_S) as port:
            port.write(b"1;1;OPEN=X\r")
            assert _read_reply(port).startswith(b"QoK")
        assert server.wait_closed(first, timeout=TIMEOUT_S)
        assert not sim.is_open
        second = server.new_port()
        with serial.Serial(second, 9600, parity="E", stopbits=2, timeout=TIMEOUT_S) as port:
            port.write(b"1;1;STATE\r")
            assert _read_reply(port) == b"QeR601000000\r"


def test_serial_link_over_the_pty(sim_pty_path: str) -> None:
    with SerialLink(sim_pty_path, LinkSettings(timeout=TIMEOUT_S)) as link:
        assert isinstance(link.exchange(Request("OPEN=NARCUSR")), Ok)
        assert link.exchange(Request("SRVON")) == Refused(6020, detail="00000")


def test_paced_pty_reply_arrives() -> None:
    sim = VirtualController()
    with PtyServer(sim, pacing=Pacing.for_baud(9600, latency=0.01)) as server:
        path = server.new_port()
        with serial.Serial(path, 9600, parity="E", stopbits=2, timeout=TIMEOUT_S) as port:
            port.write(b"1;1;OPEN=X\r")
            assert _read_reply(port).startswith(b"QoK3F")


def test_tcp_server_serves_one_client_at_a_time(sim_tcp_url: str) -> None:
    host, port = parse_tcp_url(sim_tcp_url)
    with socket.create_connection((host, port), timeout=TIMEOUT_S) as first:
        first.sendall(b"1;1;OPEN=X\r")
        assert _recv_reply(first).startswith(b"QoK3F")
        with socket.create_connection((host, port), timeout=TIMEOUT_S) as second:
            assert second.recv(16) == b""  # refused: closed at once
        first.sendall(b"1;1;STATE\r")
        assert _recv_reply(first).startswith(b"QoK")


def test_tcp_link(sim_tcp_url: str) -> None:
    with TcpLink(sim_tcp_url, LinkSettings(timeout=TIMEOUT_S)) as link:
        assert isinstance(link.exchange(Request("OPEN=X")), Ok)
        assert isinstance(link.exchange(Request("JPOSF")), Ok)


def test_tcp_server_reports_its_url() -> None:
    with TcpServer(pacing=NO_PACING) as server:
        assert server.url == f"tcp://127.0.0.1:{server.address[1]}"


def test_in_memory_link() -> None:
    sim = VirtualController(SimConfig(open_required=True))
    with open_sim_link(controller=sim) as link:
        assert link.exchange(Request("STATE")) == Refused(6010, detail="00000")
        assert isinstance(link.exchange(Request("OPEN=X")), Ok)
        assert isinstance(link.exchange(Request("CNTLON")), Ok)
        assert sim.rights
    assert not sim.is_open and not sim.rights


# --------------------------------------------------------------------------- framing


def _session() -> WireSession:
    return WireSession(VirtualController())


REQUESTS = b"1;1;OPEN=X\r1;1;CNTLON\r\n1;1;SRVON\r1;1;DSTATE\r"


def _replies(session: WireSession, pieces: list[bytes]) -> list[bytes]:
    out: list[bytes] = []
    for piece in pieces:
        out += [answer.reply for answer in session.receive(piece, 0.0)]
    return out


def test_split_input_gives_the_same_replies() -> None:
    whole = _replies(_session(), [REQUESTS])
    assert len(whole) == 4
    assert _replies(_session(), [bytes([b]) for b in REQUESTS]) == whole
    assert _replies(_session(), [REQUESTS + b"1;1;JUNK"]) == whole


def test_garbage_and_overlong_lines_get_one_refusal_each() -> None:
    session = _session()
    replies = _replies(session, [b"\xff\xfe\x80\r", b"x" * (MAX_LINE_BYTES + 10), b"tail\r"])
    assert replies == [b"QeR601000000\r", b"QeR608000000\r"]
    assert _replies(session, [b"\r\n\r", b"1;1;OPEN=X\x00"])[0].startswith(b"QoK")


@given(st.lists(st.binary(max_size=64), max_size=8))
def test_any_bytes_give_replies_never_an_exception(pieces: list[bytes]) -> None:
    session = _session()
    for reply in _replies(session, pieces):
        assert reply[:3] in (b"QoK", b"Qok", b"QeR", b"Qer") and reply.endswith(b"\r")


def test_pacing_arithmetic() -> None:
    pacing = Pacing.for_baud(9600, latency=0.1)
    assert pacing.seconds_per_char == pytest.approx(0.00125)
    assert pacing.reply_delay(10) == pytest.approx(0.1125)
    with pytest.raises(ValueError, match="positive"):
        Pacing.for_baud(0)
