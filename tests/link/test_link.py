"""Links over real transports: a fresh pty per connection (opened at 9600 8E2 through
pyserial), a real TCP socket, pyserial's loop://, and the in-memory link."""

from __future__ import annotations

import contextlib
import os
import socket
import threading
from collections.abc import Iterator

import pytest

from melfa.link import (
    LinkCancelled,
    LinkClosed,
    LinkError,
    LinkSettings,
    LinkTimeout,
    MemoryLink,
    PacedLink,
    SerialLink,
    TcpLink,
    TraceLink,
    open_link,
    parse_tcp_url,
    render,
)
from melfa.protocol import Ok, Refused, RemoteProtocolError, Request


@pytest.fixture
def pty_pair() -> Iterator[tuple[int, str]]:
    """A fresh pseudo-terminal: (master fd for the fake peer, slave path for the link)."""
    master, slave = os.openpty()
    path = os.ttyname(slave)
    yield master, path
    for fd in (master, slave):
        with contextlib.suppress(OSError):
            os.close(fd)


def read_request(master: int) -> bytes:
    data = b""
    while not data.endswith(b"\r"):
        data += os.read(master, 256)
    return data


def test_settings_default_is_9600_8e2_cr() -> None:
    s = LinkSettings()
    assert (s.baudrate, s.bytesize, s.parity, s.stopbits, s.terminator) == (9600, 8, "E", 2, b"\r")
    assert s.bits_per_char == 12
    assert s.pyserial_kwargs()["parity"] == "E"


@pytest.mark.parametrize(
    "kwargs",
    [{"baudrate": 9601}, {"parity": "X"}, {"stopbits": 3}, {"timeout": 0}, {"terminator": b"\n"}],
)
def test_settings_checked(kwargs: dict[str, object]) -> None:
    with pytest.raises(ValueError):
        LinkSettings(**kwargs)  # type: ignore[arg-type]


def test_pty_exchange_at_8e2(pty_pair: tuple[int, str]) -> None:
    master, path = pty_pair
    with SerialLink(path) as link:
        assert link.port.parity == "E" and link.port.stopbits == 2
        link.send(Request("OPEN=MELFA"))
        assert read_request(master) == b"1;1;OPEN=MELFA\r"
        os.write(master, b"QoK3F;")  # a reply in two pieces, CR LF terminated
        os.write(master, b"3F\r\n")
        assert link.read_reply() == Ok("3F;3F")
        os.write(master, b"QeR6020\r")
        assert link.read_reply() == Refused(6020)


def test_pty_garbage_is_remote_error(pty_pair: tuple[int, str]) -> None:
    master, path = pty_pair
    with SerialLink(path) as link:
        os.write(master, b"\x7f\x00junk\rQoK\r")
        with pytest.raises(RemoteProtocolError):
            link.read_reply()
        assert link.read_reply() == Ok()


def test_pty_truncated_reply_times_out_clearly(pty_pair: tuple[int, str]) -> None:
    master, path = pty_pair
    with SerialLink(path, LinkSettings(timeout=0.3)) as link:
        os.write(master, b"QoKJ1;1.0")
        with pytest.raises(LinkTimeout, match="incomplete after 9 bytes"):
            link.read_reply()
        with pytest.raises(LinkTimeout, match="no reply"):
            link.read_reply()


def test_pty_cancel_and_close_from_another_thread(pty_pair: tuple[int, str]) -> None:
    _, path = pty_pair
    link = SerialLink(path, LinkSettings(timeout=30))
    started = threading.Event()

    def cancel_when_reading() -> None:
        started.wait()
        while not link._read_lock.locked():
            pass
        link.cancel_read()

    threading.Thread(target=cancel_when_reading).start()
    started.set()
    with pytest.raises(LinkCancelled):
        link.read_reply()
    closer = threading.Timer(0.1, link.close)
    closer.start()
    with pytest.raises(LinkClosed):
        link.read_reply()
    closer.join()
    link.close()  # twice is fine
    with pytest.raises(LinkClosed):
        link.send(Request("STATE"))


def test_pty_peer_gone_is_a_clear_link_error(pty_pair: tuple[int, str]) -> None:
    master, path = pty_pair
    with SerialLink(path) as link:
        os.close(master)
        with pytest.raises(LinkClosed, match="unplugged"):
            link.read_reply()


def test_open_link_device_path_missing() -> None:
    with pytest.raises(LinkError, match="plugged in"):
        open_link("/dev/ttyUSB-melfa-none")


def test_open_link_pyserial_url_loop() -> None:
    with open_link("loop://") as link:
        link.write(b"QoK42\r")  # loop:// echoes what is written
        assert link.read_reply() == Ok("42")


def test_open_link_unknown_scheme_is_link_error() -> None:
    with pytest.raises(LinkError, match="unknown scheme"):
        open_link("nosuch://x")


@pytest.mark.parametrize("url", ["tcp://host", "tcp://:80", "tcp://h:x", "http://h:1"])
def test_bad_tcp_urls(url: str) -> None:
    with pytest.raises(LinkError, match="tcp://host:port"):
        parse_tcp_url(url)


def test_tcp_link_against_a_socket_server() -> None:
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    port = server.getsockname()[1]

    def serve() -> None:
        conn, _ = server.accept()
        with conn:
            data = b""
            while not data.endswith(b"\r"):
                data += conn.recv(100)
            assert data == b"1;1;STATE\r"
            conn.sendall(b"Qok")
            conn.sendall(b"x;1\r")
        server.close()

    thread = threading.Thread(target=serve)
    thread.start()
    with open_link(f"tcp://127.0.0.1:{port}") as link:
        assert isinstance(link, TcpLink)
        assert link.exchange(Request("STATE")) == Ok("x;1", alarm=True)
        thread.join()
        with pytest.raises(LinkClosed, match="closed the connection"):
            link.read_reply()


def test_tcp_connection_refused() -> None:
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()
    with pytest.raises(LinkError, match="cannot connect"):
        open_link(f"tcp://127.0.0.1:{port}")


def echo_number(line: bytes) -> bytes:
    return b"QoK" + line.split(b";")[-1] + b"\r"


def test_memory_link_one_reply_per_line_and_custom_terminator() -> None:
    link = MemoryLink(echo_number, LinkSettings(terminator=b"\r\n"))
    link.send(Request("OVRD=50"))
    link.send(Request("OVRD=60"))
    assert [link.read_reply(), link.read_reply()] == [Ok("OVRD=50"), Ok("OVRD=60")]
    link.hang_up()
    with pytest.raises(LinkClosed):
        link.read_reply()


def test_trace_shows_both_directions() -> None:
    lines: list[str] = []
    link = open_link("loop://", trace=True, trace_sink=lines.append)
    assert isinstance(link, TraceLink)
    link.send(Request("EMDAT10 A\x0b20 B", slot=9))
    link.read_some(deadline=float("inf"))
    assert "-> 1;9;EMDAT10 A<VT>20 B<CR>" in lines[0]
    assert "<- 1;9;EMDAT10 A<VT>20 B<CR>" in lines[1]
    assert "0d" in lines[0]
    link.close()


def test_trace_switch_from_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MELFA_TRACE", "1")
    with open_link("loop://") as link:
        assert isinstance(link, TraceLink)
    monkeypatch.setenv("MELFA_TRACE", "0")
    with open_link("loop://") as link:
        assert not isinstance(link, TraceLink)


def test_paced_link_passes_bytes_unchanged() -> None:
    link = PacedLink(MemoryLink(echo_number))
    assert link.char_time == pytest.approx(12 / 9600)
    assert link.exchange(Request("OVRD=5")) == Ok("OVRD=5")


def test_render() -> None:
    assert render(b"QoK\x0b\r\n\xff") == "QoK<VT><CR><LF>\\xff"
