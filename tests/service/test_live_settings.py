"""The rule between the server's start-up options and the desk's saved choices: the option
is a floor a saved choice may only tighten at start; a live choice looser than it lasts
until the restart, and says so."""

from __future__ import annotations

import datetime as dt

from melfa.service import live_settings as rule
from melfa.service.lab_network import parse_networks, within
from melfa.service.live_settings import Choice, Networks, Origin
from melfa.vocab.desk import SettingSource

AT = dt.datetime(2026, 11, 27, 8, 0, tzinfo=dt.UTC)
LAB = parse_networks(["192.168.10.0/24"])


def nets(*texts: str) -> Networks:
    return parse_networks(texts)


def desk(by: str = "ivy", until_restart: bool = False, cut_from: Networks = ()) -> Origin:
    return Origin(SettingSource.DESK, by, AT, until_restart, cut_from)


def test_the_gate_option_is_a_floor_a_saved_off_cannot_lower() -> None:
    assert rule.gate_at_start(False, None) == (False, rule.DEFAULT)
    assert rule.gate_at_start(True, None) == (True, rule.COMMAND_LINE)
    assert rule.gate_at_start(True, Choice(False, "ivy", AT)) == (True, rule.COMMAND_LINE)
    assert rule.gate_at_start(False, Choice(True, "ivy", AT)) == (True, desk())
    assert rule.gate_at_start(False, Choice(False, "ivy", AT)) == (False, desk())
    # Live: off under the option lasts until the restart; on never does.
    assert rule.gate_switched(True, Choice(False, "ivy", AT)) == desk(until_restart=True)
    assert rule.gate_switched(True, Choice(True, "ivy", AT)) == desk()
    assert rule.gate_switched(False, Choice(False, "ivy", AT)) == desk()


def test_saved_networks_are_kept_only_inside_the_options() -> None:
    assert rule.networks_at_start((), None) == ((), rule.DEFAULT)
    assert rule.networks_at_start(LAB, None) == (LAB, rule.COMMAND_LINE)
    room = nets("192.168.10.0/26")
    assert rule.networks_at_start(LAB, Choice(room, "ivy", AT)) == (room, desk())
    anywhere = Choice((), "ivy", AT)
    assert rule.networks_at_start(LAB, anywhere) == (LAB, rule.COMMAND_LINE)
    outside = nets("10.0.0.0/8")
    assert rule.networks_at_start(LAB, Choice(outside, "ivy", AT)) == (LAB, rule.COMMAND_LINE)
    # Only partly inside: cut to that part, and the origin says what was saved.
    wider = nets("192.168.0.0/16", "10.0.0.0/8")
    assert rule.networks_at_start(LAB, Choice(wider, "ivy", AT)) == (LAB, desk(cut_from=wider))
    part = nets("192.168.10.0/26", "10.0.0.0/8")
    assert rule.networks_at_start(LAB, Choice(part, "ivy", AT)) == (room, desk(cut_from=part))
    assert rule.networks_at_start((), Choice((), "ivy", AT)) == ((), desk())  # no option: as saved
    assert rule.networks_at_start((), Choice(outside, "ivy", AT)) == (outside, desk())
    # Live: looser than the option lasts until the restart.
    assert rule.networks_switched(LAB, Choice((), "ivy", AT)) == desk(until_restart=True)
    assert rule.networks_switched(LAB, Choice(outside, "ivy", AT)) == desk(until_restart=True)
    # ...and the restart then keeps the part inside.
    for chosen in (wider, part):
        looser = desk(until_restart=True, cut_from=chosen)
        assert rule.networks_switched(LAB, Choice(chosen, "ivy", AT)) == looser
    assert rule.networks_switched(LAB, Choice(room, "ivy", AT)) == desk()
    assert rule.networks_switched((), Choice((), "ivy", AT)) == desk()


def test_within_takes_the_smaller_of_each_nested_pair_and_skips_the_rest() -> None:
    floor = nets("192.168.10.0/24", "fd00::/8")
    mixed = nets("192.168.10.7", "192.168.0.0/16", "10.0.0.0/8", "fd00:1::/32", "::1")
    assert within(mixed, floor) == nets("192.168.10.7", "192.168.10.0/24", "fd00:1::/32")
    assert within((), floor) == ()
    assert within(mixed, ()) == ()
