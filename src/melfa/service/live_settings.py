"""The instructor's live settings of the lab robot — the simulation gate and the lab's
networks — at start-up and when switched: which wins when the server's start-up option and
the desk's saved choice differ, and where the setting in force came from. Pure: the web
reads the saved choices from the store and hands them here.

The rule: **the start-up option is a floor that the desk's saved choice may only tighten
at start.**

- The gate: ``melfa serve --require-simulation`` turns it on whatever was saved (a saved
  "off" cannot lower it); without the option, the saved choice; with neither, off.
- The lab's networks: with ``--lab-network``, a saved list is kept only where it lies
  inside the option's networks (`melfa.service.lab_network.within`); a saved "anywhere",
  or a list outside them, gives the option's. Without the option, the saved list (which
  may be anywhere); with neither, anywhere. A saved list only partly inside is cut to
  that part, and the desk says so (`Origin.cut_from`): what holds is not all it shows
  was saved.

Live, staff switch either way on the desk (saved, audited, at once for every door); a
choice looser than the floor lasts until the server restarts (`Origin.until_restart`), and
the desk says so. A server restart (a crash, a reboot, an update) never silently drops a
gate the instructor set: it is saved before it applies.
"""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass
from typing import Generic, TypeVar

from melfa.service.lab_network import Network, within
from melfa.vocab.desk import SettingSource

V = TypeVar("V")
Networks = tuple[Network, ...]


@dataclass(frozen=True)
class Choice(Generic[V]):
    """What a member of staff chose on the desk (saved): the value, who, when."""

    value: V
    by: str
    at: dt.datetime


@dataclass(frozen=True)
class Origin:
    """Where the setting in force came from, as the desk words it."""

    source: SettingSource
    by: str | None = None
    at: dt.datetime | None = None
    until_restart: bool = False
    """A desk choice looser than the start-up option: a restart goes back to the option."""
    cut_from: Networks = ()
    """The desk's networks when they lie only partly inside the start-up option: only that
    part holds after a start (cut then; with `until_restart`, at the next one). Empty
    otherwise."""


DEFAULT = Origin(SettingSource.DEFAULT)
COMMAND_LINE = Origin(SettingSource.COMMAND_LINE)


def _desk(choice: Choice[V], until_restart: bool = False, cut_from: Networks = ()) -> Origin:
    return Origin(SettingSource.DESK, choice.by, choice.at, until_restart, cut_from)


def gate_at_start(option: bool, saved: Choice[bool] | None) -> tuple[bool, Origin]:
    """The gate a server starts with (see the module doc)."""
    if option:
        return True, COMMAND_LINE
    if saved is not None:
        return saved.value, _desk(saved)
    return False, DEFAULT


def gate_switched(option: bool, choice: Choice[bool]) -> Origin:
    """Where the gate comes from once staff switched it (off under the option: until the
    restart)."""
    return _desk(choice, until_restart=option and not choice.value)


def networks_at_start(option: Networks, saved: Choice[Networks] | None) -> tuple[Networks, Origin]:
    """The lab's networks a server starts with (see the module doc)."""
    if saved is None:
        return option, COMMAND_LINE if option else DEFAULT
    if not option:
        return saved.value, _desk(saved)
    kept = within(saved.value, option)
    if not kept:  # anywhere, or nothing of it inside the option's: the option's
        return option, COMMAND_LINE
    return kept, _desk(saved, cut_from=() if kept == saved.value else saved.value)


def networks_switched(option: Networks, choice: Choice[Networks]) -> Origin:
    """Where the networks come from once staff set them (looser than the option: until
    the restart, which keeps only what lies inside)."""
    at_start, then = networks_at_start(option, choice)
    return _desk(choice, until_restart=at_start != choice.value, cut_from=then.cut_from)


__all__ = [
    "COMMAND_LINE",
    "DEFAULT",
    "Choice",
    "Networks",
    "Origin",
    "gate_at_start",
    "gate_switched",
    "networks_at_start",
    "networks_switched",
]
