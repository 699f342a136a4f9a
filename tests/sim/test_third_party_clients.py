"""Real third-party clients of the controller family drive `melfa sim`, unmodified.

- ctu-mitsubishi (PyPI, pinned; an RV-6S at CTU over serial at 38400 8E2): never sends OPEN,
  reads replies with pyserial's ``readline()`` (LF: its lab ran CTERM232 = 1), writes a
  running program's variables with ``HOT``. Its resident program is rebuilt from its client
  code in ``examples/ctu_mitsubishi/MOVEIT.MB4``. Through a real pty, strict and lenient.
- The Robotics Library's MitsubishiR3 (TCP) sends each request with no terminator at all
  and reads one ``recv``: its request sequence, replayed on a real socket.
"""

from __future__ import annotations

import socket
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from melfa.sim import NO_PACING, PtyServer, SimConfig, TcpServer, VirtualController
from melfa.sim.config import Terminator

ctu_mitsubishi = pytest.importorskip("ctu_mitsubishi")

MOVEIT = Path(__file__).parents[2] / "examples" / "ctu_mitsubishi" / "MOVEIT.MB4"


def _controller(strict: bool) -> VirtualController:
    controller = VirtualController(
        SimConfig(strict=strict, cterm=Terminator.CRLF),
        programs={"MOVEIT": MOVEIT.read_text(encoding="utf-8")},
    )
    # The operator switched the servo on at the panel (ctu-mitsubishi never sends SRVON).
    for request in (b"1;1;CNTLON\r", b"1;1;SRVON\r", b"1;1;CNTLOFF\r"):
        assert controller.handle(request, 0.0).startswith(b"QoK")
    return controller


@pytest.fixture(params=[True, False], ids=["strict", "lenient"])
def ctu_robot(request: pytest.FixtureRequest) -> Iterator[tuple[object, VirtualController]]:
    controller = _controller(request.param)
    with PtyServer(controller, pacing=NO_PACING) as server:
        robot = ctu_mitsubishi.Rv6s(port=server.new_port())
        try:
            yield robot, controller
        finally:
            robot.close_connection()


def test_ctu_mitsubishi_initialize_get_q_move_wait_stop(
    ctu_robot: tuple[object, VirtualController],
) -> None:
    robot, controller = ctu_robot
    robot.initialize()  # type: ignore[attr-defined]
    assert controller.program_running
    start = robot.get_q()  # type: ignore[attr-defined]
    assert np.allclose(np.rad2deg(start), [0, 0, 90, 0, 90, 0], atol=0.01)
    target = np.deg2rad([10.0, 5.0, 95.0, 0.0, 80.0, 0.0])
    robot.move_to_q(target)  # type: ignore[attr-defined]
    assert robot.wait_for_motion_stop(timeout=30)  # type: ignore[attr-defined]
    # ctu-mitsubishi's "stopped": every joint within its tolerance (0.0087 rad) of the target.
    assert np.allclose(robot.get_q(), target, atol=0.0087)  # type: ignore[attr-defined]
    robot.stop_robot()  # type: ignore[attr-defined]
    controller.advance(controller.now + 1.0)
    assert not controller.program_running


# The Robotics Library's MitsubishiR3 requests (written from its source's sequence, not
# copied): rights, status, an edit of a program at the edit slot, run, hand, EXEC, errors.
RL_SEQUENCE = [
    ("1;1;CNTLON", b"QoK"),
    ("1;1;DSTATE", b"QoK"),
    ("1;1;NEW", b"QoK"),
    ("1;1;LOAD=RL", b"QoK"),
    ("1;9;ECLR", b"QoK"),
    ("1;9;EMDAT10 MOV P1\x0b20 END", b"QoK"),
    ("1;1;SAVE", b"QoK"),
    ("1;1;HNDON1", b"QoK"),
    ("1;9;EXECOVRD 10", b"QoK"),
    ("1;1;ERRORMES6010", b"QoK"),
    ("1;1;CNTLOFF", b"QoK"),
]


def test_the_robotics_library_sequence_without_terminators() -> None:
    controller = VirtualController(SimConfig(strict=False))
    with (
        TcpServer(controller, pacing=NO_PACING) as server,
        socket.create_connection(server.address, timeout=5) as conn,
    ):
        for request, head in RL_SEQUENCE:
            conn.sendall(request.encode("ascii"))  # no CR, no LF, no NUL
            reply = conn.recv(256)
            assert reply.startswith(head) and reply.endswith(b"\r"), (request, reply)
    assert controller.store.get("RL") is not None


@pytest.mark.parametrize("strict", [True, False], ids=["strict", "lenient"])
def test_what_real_controllers_answered_is_answered(strict: bool) -> None:
    """Slot 9 position reads and DSTATE (a real CR1-571), JPOSF. (a real RV-1A), and a
    session that never sent OPEN (three real clients)."""
    controller = VirtualController(SimConfig(strict=strict))
    for request, head in [
        (b"1;9;JPOSF\r", b"QoKJ1;"),
        (b"1;9;PPOSF\r", b"QoKX;"),
        (b"1;1;DSTATE\r", b"QoK"),
        (b"1;1;JPOSF.\r", b"QoKJ1;"),
        (b"1;1;STATE\r", b"QoK"),
    ]:
        assert controller.handle(request, 0.0).startswith(head), request
    assert controller.handle(b"1;1;STATE\n", 0.0).startswith(b"QoK")


def test_the_manual_rule_open_first_is_a_setting() -> None:
    controller = VirtualController(SimConfig(open_required=True))
    assert controller.handle(b"1;1;STATE\r", 0.0) == b"QeR601000000\r"


def test_state_after_a_cycle_run_ends_is_the_recorded_idle_state() -> None:
    controller = VirtualController(SimConfig(strict=True), programs={"SHORT": "10 M1=1\n20 END\n"})
    for request in (b"1;1;CNTLON\r", b"1;1;SRVON\r", b"1;1;RUNSHORT;1\r"):
        assert controller.handle(request, 0.0).startswith(b"QoK")
    assert controller.handle(b"1;1;CNTLOFF\r", 0.0) == b"QoK\r"
    # [TRACE K9b-PROG] QoK;0;100;0;21120;0;1;;;;;;;;;REP;START;1;0
    reply = controller.handle(b"1;1;STATE\r", 5.0)
    assert reply == b"QoK;0;100;0;21120;0;1;;;;;;;;;REP;START;1;0\r"
