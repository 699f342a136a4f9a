"""The robot profile: settings `melfa doctor` found on a controller, used by every later
command and by `melfa serve` for the same ``--robot``.

One JSON file, ``$MELFA_PROFILE`` or ``$XDG_CONFIG_HOME/melfa/profile.json`` (``~/.config``
by default), holding per ``--robot`` value the `RobotSettings` fields doctor could settle
(only those; everything else keeps its default) and what it saw (banner, when)::

    {"robots": {"/dev/ttyUSB0": {"settings": {"stop_slot": 1, "prtver_handshakes": false},
                                 "controller": "RV-6S CRn-5xx Ver.K4a", "written": "…"}}}
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import json
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final

from melfa.robot.errors import RobotError
from melfa.robot.settings import JogMethod, RobotSettings

PROFILE_ENV: Final = "MELFA_PROFILE"
PROFILE_FIELDS: Final = (
    "stop_slot",
    "prtver_handshakes",
    "jog",
    "confirm_counts",
    "edit_slot",
    "listp_answered",
)
"""The settings doctor may write (each one a [GUESS] it can probe)."""


def profile_path() -> Path:
    """Where the profile lives."""
    explicit = os.environ.get(PROFILE_ENV)
    if explicit:
        return Path(explicit)
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "melfa" / "profile.json"


def _read(path: Path) -> dict[str, Any]:
    if not path.exists():
        return {"robots": {}}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise RobotError(
            f"robot profile {path} is unreadable ({exc}); delete it or run `melfa doctor` again"
        ) from None
    if not isinstance(data, dict) or not isinstance(data.get("robots"), dict):
        raise RobotError(f"robot profile {path} is not a melfa profile")
    return data


def _coerce(name: str, value: object) -> object:
    if name == "jog":
        return JogMethod(value)
    return value


def profile_settings(spec: str, base: RobotSettings | None = None) -> RobotSettings:
    """`RobotSettings` for ``spec``: ``base`` (defaults) with what doctor found."""
    settings = base or RobotSettings()
    entry = _read(profile_path())["robots"].get(spec)
    if not isinstance(entry, dict):
        return settings
    found = entry.get("settings", {})
    changes = {
        name: _coerce(name, found[name])
        for name in PROFILE_FIELDS
        if isinstance(found, dict) and name in found
    }
    try:
        return dataclasses.replace(settings, **changes)  # type: ignore[arg-type]
    except (TypeError, ValueError) as exc:
        raise RobotError(f"robot profile {profile_path()}: {exc}") from None


def save_profile(spec: str, found: Mapping[str, object], controller: str) -> Path:
    """Record ``found`` (PROFILE_FIELDS only) for ``spec``; returns the file written."""
    path = profile_path()
    data = _read(path)
    settings = {
        k: (v.value if isinstance(v, JogMethod) else v)
        for k, v in found.items()
        if k in PROFILE_FIELDS
    }
    data["robots"][spec] = {
        "settings": settings,
        "controller": controller,
        "written": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n", encoding="utf-8")
    tmp.replace(path)
    return path
