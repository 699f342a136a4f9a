"""The Qt-free layers against a real server: sign-in, CSRF, check, refusals, live feed."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from melfa.desktop.api import ApiClient, ApiError, ServerUnreachable
from melfa.desktop.files import FileKind, FileRefused, read_file
from melfa.desktop.live import FeedStatus, LiveFeed
from melfa.desktop.messages import LiveMessage
from melfa.live.messages import StateMessage
from melfa.vocab.link import LinkStatus
from tests.desktop.conftest import Server
from tests.serving import free_port


def test_sign_in_keeps_the_session_and_reads_state(server: Server) -> None:
    client = ApiClient(server.url)
    user = client.login("admin", server.password)
    assert (user.username, user.role) == ("admin", "admin")
    state = client.state()
    assert state.link is LinkStatus.CONNECTED
    assert state.joints is not None and len(state.joints) == 6
    client.logout()
    with pytest.raises(ApiError) as info:
        client.state()
    assert (info.value.status, info.value.code) == (401, "not-signed-in")


def test_wrong_password_is_the_servers_refusal(server: Server) -> None:
    with pytest.raises(ApiError) as info:
        ApiClient(server.url).login("admin", "not-the-password")
    assert (info.value.status, info.value.code) == (401, "wrong-login")
    assert "Wrong username or password" in info.value.message


def test_no_server_is_unreachable_not_a_refusal() -> None:
    with pytest.raises(ServerUnreachable) as info:
        ApiClient(f"http://127.0.0.1:{free_port()}").login("admin", "x")
    assert "refused" in info.value.reason.lower()


def test_check_lists_diagnostics_with_positions(server: Server) -> None:
    client = ApiClient(server.url)
    client.login("admin", server.password)
    result = client.check("10 MOV Pa\n20 FOO 1\n", "DEF POS Pa=(400,0,600,180,0,180)(7,0)\n")
    assert not result.ok
    [error] = result.program_errors
    assert (error.line, error.column) == (2, 4)
    assert "FOO" in error.message
    assert str(error).startswith("2:4 error: ")


def test_load_refused_for_errors_carries_the_diagnostics(server: Server) -> None:
    client = ApiClient(server.url)
    client.login("admin", server.password)
    with pytest.raises(ApiError) as info:
        client.load_project("10 FOO\n", "")
    assert info.value.code == "program-has-errors"
    assert [(d.line, d.column) for d in info.value.diagnostics] == [(1, 4)]


def test_file_rules(tmp_path: Path) -> None:
    (tmp_path / "pick.mb4").write_bytes(b"10 MOV P1\r\n20 END\r\n")
    (tmp_path / "pick.txt").write_text("10 END\n")
    (tmp_path / "blob.MB4").write_bytes(b"\x00\x01")
    assert read_file(tmp_path / "pick.mb4", FileKind.PROGRAM).text == "10 MOV P1\n20 END\n"
    with pytest.raises(FileRefused, match=r"wrong extension \(\.txt\): choose a \.MB4 program"):
        read_file(tmp_path / "pick.txt", FileKind.PROGRAM)
    with pytest.raises(FileRefused, match=r"choose a \.POS points file"):
        read_file(tmp_path / "pick.mb4", FileKind.POINTS)
    with pytest.raises(FileRefused, match="not a text file"):
        read_file(tmp_path / "blob.MB4", FileKind.PROGRAM)
    with pytest.raises(FileRefused, match="no such file"):
        read_file(tmp_path / "gone.MB4", FileKind.PROGRAM)


def test_live_feed_delivers_state_and_is_refused_without_a_session(server: Server) -> None:
    client = ApiClient(server.url)
    client.login("admin", server.password)
    got_state = threading.Event()
    messages: list[LiveMessage] = []
    statuses: list[FeedStatus] = []

    def on_message(message: LiveMessage) -> None:
        messages.append(message)
        if isinstance(message, StateMessage):
            got_state.set()

    feed = LiveFeed(
        client.websocket_url, client.cookie_header(), on_message, lambda s, _: statuses.append(s)
    )
    feed.start()
    try:
        assert got_state.wait(20), statuses
    finally:
        feed.close()
    assert not feed.running
    assert statuses[0] is FeedStatus.CONNECTING and FeedStatus.CONNECTED in statuses
    assert statuses[-1] is FeedStatus.CLOSED

    refused = threading.Event()
    details: list[str] = []

    def on_status(status: FeedStatus, detail: str) -> None:
        if status is FeedStatus.REFUSED:
            details.append(detail)
            refused.set()

    anonymous = LiveFeed(client.websocket_url, {}, lambda _: None, on_status)
    anonymous.start()
    try:
        assert refused.wait(20)
    finally:
        anonymous.close()
    assert not anonymous.running


def test_the_chosen_target_gets_the_commands(server: Server) -> None:
    client = ApiClient(server.url)
    client.login("admin", server.password)
    client.target = "mine"
    assert client.websocket_url.endswith("/api/ws?target=mine")
    client.exec_statement("SERVO ON")  # on the user's own simulator, made by this call
    wait = threading.Event()
    for _ in range(100):
        if client.state().servo:
            break
        wait.wait(0.05)
    assert client.state().servo is True
    client.target = "lab"
    assert client.websocket_url.endswith("/api/ws")
