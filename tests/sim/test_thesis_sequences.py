"""protocol.md §4.2: the thesis's exact command sequences (S7) all succeed on the simulator.

Every request is sent byte for byte as the thesis sends it, prefix included. The timing the
thesis relies on (2 s after SRVON, 1 s after SRVOFF, polling while busy) is reproduced with
the injected clock.
"""

from __future__ import annotations

import pytest

from melfa.protocol.answers import Position, State
from melfa.protocol.emdat import chunk_emdat
from melfa.sim import VirtualController
from melfa.sim.config import STRICT_ENV
from tests.fixtures_sim import Driver


@pytest.fixture(autouse=True)
def _strict(monkeypatch: pytest.MonkeyPatch) -> None:
    """The thesis ran these on a real CR2B: a strict simulator must answer all of them."""
    monkeypatch.setenv(STRICT_ENV, "1")


def send(drive: Driver, raw: str) -> bytes:
    return drive.controller.handle(raw.encode("ascii") + b"\r", drive.now)


def all_ok(drive: Driver, *requests: str) -> None:
    for raw in requests:
        reply = send(drive, raw)
        assert reply.startswith(b"QoK"), (raw, reply)
        drive.wait(0.15)


def init(drive: Driver) -> None:
    """Item 1: S6 `initRobot`."""
    all_ok(drive, "1;1;OPEN=NARCUSR", "1;1;CNTLON", "1;1;RSTPRG", "1;1;PRGLOAD=COSIROP")
    all_ok(drive, "1;1;SRVON")
    drive.wait(2.0)
    all_ok(drive, "1;1;EXECBASE (0,0,0,0,0,0,0,0)")


def deinit(drive: Driver) -> None:
    all_ok(drive, "1;1;SRVOFF")
    drive.wait(1.0)
    all_ok(drive, "1;1;CNTLOFF", "1;1;CLOSE")


def wait_not_busy(drive: Driver) -> int:
    """S6 `isBusy()`: `EXECREM Waiting...` every 200 ms until it is not 5640."""
    polls = 0
    while (reply := send(drive, "1;1;EXECREM Waiting...")) == b"QeR564000000\r":
        polls += 1
        drive.wait(0.2)
        assert polls < 100
    assert reply == b"QoK\r"
    return polls


def test_item1_init_statements_and_deinit(drive: Driver) -> None:
    init(drive)
    all_ok(drive, "1;1;EXECOVRD 20", "1;1;EXECTOOL (0,0,100,0,0,0)")
    all_ok(drive, "1;1;EXECJCOSIROP=(30.00,10.00,100.00,0.00,60.00,0.00)")
    all_ok(drive, "1;1;EXECMOV JCOSIROP")
    assert wait_not_busy(drive) > 0  # a real move at 20 % takes several polls
    joints = Position.parse(send(drive, "1;1;JPOSF")[3:-1].decode())
    assert joints.values("J1", "J2", "J3", "J5") == (30.0, 10.0, 100.0, 60.0)
    all_ok(drive, "1;1;EXECPCOSIROP=(350.00,100.00,500.00,180.00,0.00,180.00)(7,0)")
    all_ok(drive, "1;1;EXECMVS PCOSIROP")
    wait_not_busy(drive)
    pose = Position.parse(send(drive, "1;1;PPOSF")[3:-1].decode())
    assert pose.values("X", "Y", "Z") == (350.0, 100.0, 500.0)
    deinit(drive)


def test_item2_to_4_connect_upload_program_and_points(drive: Driver) -> None:
    program = ["10 SERVO ON", "20 OVRD 20", "30 MOV PPIRAM", "40 HOPEN 1", "60 END"]
    points = ["PPIRAM=(400.00,0.00,600.00,180.00,0.00,180.00)(7,0)"]
    # item 2: connect for load
    all_ok(
        drive,
        "1;1;OPEN=NARCUSR",
        "1;1;PARRLNG",
        "1;1;PDIRTOP",
        "1;1;PPOSF",
        "1;1;PARMEXTL",
        "1;1;KEYWDptest",
    )
    # item 3: upload a program: clear old lines by number, then the lines
    prefix = ("1;1;NEW", "1;1;LOAD=1", "1;1;PRTVERLISTL", "1;1;PRTVEREMDAT", "1;9;LISTL<")
    all_ok(drive, *prefix)
    numbers = [line.split(" ", 1)[0] for line in program]
    for chunk in chunk_emdat(numbers):
        all_ok(drive, chunk.request.to_bytes().decode().rstrip("\r"))
    for chunk in chunk_emdat(program):
        all_ok(drive, chunk.request.to_bytes().decode().rstrip("\r"))
    all_ok(drive, "1;1;SAVE")
    # item 4: points into the same program
    all_ok(drive, *prefix)
    for chunk in chunk_emdat(points):
        all_ok(drive, chunk.request.to_bytes().decode().rstrip("\r"))
    all_ok(drive, "1;1;SAVE")
    # item 7
    all_ok(drive, "1;1;CLOSE")
    sim = drive.controller
    stored = sim.store.get("1")
    assert stored is not None
    assert [stored.lines[n] for n in sorted(stored.lines)] == program
    assert list(stored.positions) == ["PPIRAM"]


def test_item5_and_6_run_then_delete() -> None:
    sim = VirtualController(programs={"1": "10 OVRD 20\n20 OVRD 30\n30 END\n"})
    drive = Driver(sim)
    all_ok(drive, "1;1;OPEN=NARCUSR")
    # item 5: run, poll the STATE busy flag once per second
    all_ok(drive, "1;1;CNTLON", "1;1;SLOTINIT", "1;1;RUN1;1")
    polls = 0
    while State.parse(send(drive, "1;1;STATE")[3:-1].decode()).status.run & 0x40:
        polls += 1
        drive.wait(1.0)
        assert polls < 60
    all_ok(drive, "1;1;CNTLOFF")
    # item 6: delete
    all_ok(drive, "1;1;SAVE", "1;1;CNTLON", "1;1;RSTPRG", "1;1;CNTLOFF", "1;1;FDEL1")
    assert send(drive, "1;1;PDIR<").startswith(b"QoK;;;0;")  # memory empty again
    all_ok(drive, "1;1;CLOSE")


def test_thesis_reconnects_for_every_command(drive: Driver) -> None:
    """S7 repeats init and deinit around every single statement."""
    for target in ("(10,0,90,0,90,0)", "(20,0,90,0,90,0)", "(0,0,90,0,90,0)"):
        init(drive)
        all_ok(drive, f"1;1;EXECJCOSIROP={target}", "1;1;EXECMOV JCOSIROP")
        wait_not_busy(drive)
        deinit(drive)
    all_ok(drive, "1;1;OPEN=NARCUSR")
    assert send(drive, "1;1;JPOSF").startswith(b"QoKJ1;0.00;J2;0.00;J3;90.00;")
