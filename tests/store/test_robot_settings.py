"""The desk's settings of a shared robot in a real SQLite file: saved with who and when,
the last choice wins, another robot's are its own, and a reopened file (a restarted
server) reads them back."""

from __future__ import annotations

from pathlib import Path

from melfa.store import Store
from tests.store.conftest import CHEAP, FakeClock


def test_a_saved_setting_survives_reopening_the_file(db_path: Path, clock: FakeClock) -> None:
    with Store(db_path, clock=clock, hasher=CHEAP) as store:
        settings = store.robot_settings
        assert settings.load("lab") == {}
        first = settings.save("lab", "require_simulation", True, "ivy")
        clock.advance(minutes=5)
        settings.save("lab", "lab_networks", ["192.168.10.0/24"], "ivy")
        clock.advance(minutes=5)
        last = settings.save("lab", "require_simulation", False, "admin")  # the last choice wins
        settings.save("lab2", "require_simulation", True, "ola")
        assert first.at < last.at == clock.now
    with Store(db_path, clock=clock, hasher=CHEAP) as reopened:
        saved = reopened.robot_settings.load("lab")
        assert set(saved) == {"require_simulation", "lab_networks"}
        gate = saved["require_simulation"]
        assert (gate.value, gate.by, gate.at) == (False, "admin", last.at)
        assert saved["lab_networks"].value == ["192.168.10.0/24"]
        assert reopened.robot_settings.load("lab2")["require_simulation"].value is True
