"""Upload confirmation against the variants real controllers give: PDIR with empty counts or
positions counted in the steps, a bit-flipped SAVE answer, --verify without LISTP.

After SAVE the controller holds the program; when PDIR cannot confirm what it holds the
upload says "saved, but not confirmed" (`SavedNotConfirmed`, `melfa upload` exit 4), never
"failed". Through the fault relay on a real pty (the relay's controller really saves).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from typer.testing import CliRunner

from melfa.cli import app
from melfa.link import LinkError
from melfa.robot import SavedNotConfirmed
from tests.plans import project
from tests.robot.relay import Fault, FaultRelay
from tests.robot.test_fault_relay import POINTS, PROGRAM, SILENT_S, held_program, robot_on

PDIR_VARIANTS = {
    # 41 steps and 3 positions were sent.
    "counts empty": (b"QoK1.MB4;964;24-01-0100:00:00;2;223488;12;;;;0;0;0;0\r", False),
    "positions counted in the steps": (
        b"QoK1.MB4;964;24-01-0100:00:00;2;223488;12;;44;3;0;0;0;0\r",
        True,
    ),
    "positions field empty": (b"QoK1.MB4;964;24-01-0100:00:00;2;223488;12;;41;;0;0;0;0\r", False),
    "short entry": (b"QoK1.MB4;964;24-01-0100:00:00\r", False),
    "other counts": (b"QoK1.MB4;964;24-01-0100:00:00;2;223488;12;;40;2;0;0;0;0\r", False),
}


@pytest.fixture
def relay() -> Iterator[FaultRelay]:
    made = FaultRelay()
    yield made
    made.close()


@pytest.mark.parametrize("variant", sorted(PDIR_VARIANTS))
def test_pdir_variants_confirm_or_say_saved_but_not_confirmed(
    relay: FaultRelay, variant: str
) -> None:
    payload, confirms = PDIR_VARIANTS[variant]
    relay.add(Fault.replace("PDIR", payload))
    with robot_on(relay) as robot:
        if confirms:
            report = robot.load_project(project(PROGRAM, POINTS))
            assert report.held is not None and report.held.lines == 44
        else:
            with pytest.raises(SavedNotConfirmed, match="saved, but not confirmed") as caught:
                robot.load_project(project(PROGRAM, POINTS))
            assert "None" not in str(caught.value)
            assert caught.value.held is not None and caught.value.held.name == "1"
    assert held_program(relay) is not None and len(held_program(relay) or []) == 41


def test_a_bit_flipped_save_answer_gets_the_pdir_look(relay: FaultRelay) -> None:
    relay.add(Fault.replace("SAVE", b"QoJ\r"))  # K (0x4B) with its lowest bit flipped
    with robot_on(relay) as robot, pytest.raises(SavedNotConfirmed) as caught:
        robot.load_project(project(PROGRAM, POINTS))
    assert "garbled" in str(caught.value) and "probably saved" in str(caught.value)
    assert relay.commands().count("PDIR<") >= 1


def test_verify_reads_steps_back_without_listp(relay: FaultRelay) -> None:
    with robot_on(relay) as robot:
        report = robot.load_project(project(PROGRAM, POINTS), verify=True)
    assert report.verified
    assert "counted by PDIR, not read back" in report.confirmation
    assert any(c.startswith("LISTL") for c in relay.commands())
    assert not any(c.startswith("LISTP") for c in relay.commands())


def test_upload_cli_exits_4_when_saved_but_not_confirmed(
    relay: FaultRelay, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("MELFA_PROFILE", str(tmp_path / "profile.json"))
    program = tmp_path / "P.MB4"
    program.write_text(PROGRAM, encoding="utf-8")
    relay.add(Fault.replace("PDIR", PDIR_VARIANTS["counts empty"][0]))
    result = CliRunner().invoke(
        app, ["upload", str(program), "--robot", relay.new_port(), "--timeout", "5", "--force"]
    )
    assert result.exit_code == 4, result.output
    assert "saved, but not confirmed" in result.output and "Traceback" not in result.output


def test_an_upload_on_a_dead_link_fails_at_the_first_failure(relay: FaultRelay) -> None:
    relay.add(Fault.hang_up(";EMDAT", nth=2))
    with robot_on(relay) as robot, pytest.raises(LinkError):
        robot.load_project(project(PROGRAM, POINTS))
    sent = relay.commands()
    assert sent[-1].startswith("EMDAT"), sent and sent.count("NEW") == 1 and "SAVE" not in sent


def test_after_a_lost_emdat_answer_the_next_upload_starts_clean(relay: FaultRelay) -> None:
    relay.add(Fault.drop(";EMDAT", nth=2))
    with robot_on(relay, SILENT_S) as robot:
        with pytest.raises(LinkError):
            robot.load_project(project(PROGRAM, POINTS))
        assert "SAVE" not in relay.commands()
        robot.link.settings = robot.link.settings.with_(timeout=10.0)
        report = robot.load_project(project(PROGRAM, POINTS))
    assert report.held is not None and report.held.lines == 41
    assert held_program(relay) is not None and len(held_program(relay) or []) == 41
