"""``--robot`` values: parsed and checked in this one place (CLI, ``melfa serve``, ``melfa
ros``, the service and the opener all call `parse_robot`).

An empty or malformed value is refused (`RobotSpecError`, exit 2 on the command line): an
empty ``--robot ''`` must never fall back to a throw-away simulator while the user thinks
the real arm is being driven. Only *no value at all* (no option, no ``$MELFA_ROBOT``)
means ``sim``.

>>> parse_robot("tcp://127.0.0.1:7000").kind, parse_robot(None, env={}).text
(<SpecKind.TCP: 'tcp'>, 'sim')
>>> parse_robot("", env={})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
melfa.link.spec.RobotSpecError: --robot is empty: give a serial device (/dev/ttyUSB0, COM3), ...
"""

from __future__ import annotations

import enum
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Final

SIM_SPEC: Final = "sim"
ROBOT_ENV: Final = "MELFA_ROBOT"

_FORMS: Final = "a serial device (/dev/ttyUSB0, COM3), tcp://host:port, a pyserial URL, or sim"
_URL = re.compile(r"([a-z][a-z0-9+.-]*)://(.*)", re.IGNORECASE)
_HOST_PORT = re.compile(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):(\d{1,5})")
_DEVICE = re.compile(r"(/[^\s;]+|COM\d{1,3}|\\\\\.\\COM\d{1,3})", re.IGNORECASE)
_PYSERIAL_SCHEMES: Final = frozenset({"socket", "rfc2217", "loop", "spy", "alt", "hwgrep"})


class RobotSpecError(ValueError):
    """A ``--robot`` value that names nothing we can open; the message says what is wrong."""


class SpecKind(enum.Enum):
    """What a ``--robot`` value names."""

    SIM = "sim"
    SERIAL = "serial"
    TCP = "tcp"
    URL = "url"


@dataclass(frozen=True)
class RobotSpec:
    """A checked ``--robot`` value."""

    text: str
    kind: SpecKind

    @property
    def is_sim(self) -> bool:
        """The in-process virtual controller."""
        return self.kind is SpecKind.SIM

    def __str__(self) -> str:
        return self.text


def parse_robot(
    value: str | None, *, env: Mapping[str, str] | None = None, option: str = "--robot"
) -> RobotSpec:
    """Check ``value`` (None: ``$MELFA_ROBOT``, else ``sim``); `RobotSpecError` if bad."""
    environ = os.environ if env is None else env
    where = option
    if value is None:
        if ROBOT_ENV not in environ:
            return RobotSpec(SIM_SPEC, SpecKind.SIM)
        value, where = environ[ROBOT_ENV], f"${ROBOT_ENV}"
    text = value.strip()
    if not text:
        raise RobotSpecError(f"{where} is empty: give {_FORMS}")
    if text != value:
        raise RobotSpecError(f"{where} {value!r} has spaces around it")
    if text == SIM_SPEC or text.startswith(SIM_SPEC + ":"):
        return RobotSpec(text, SpecKind.SIM)
    url = _URL.fullmatch(text)
    if url is not None:
        scheme, rest = url.group(1).lower(), url.group(2)
        if scheme == "tcp":
            match = _HOST_PORT.fullmatch(rest)
            if match is None or not 0 < int(match.group(2)) < 65536:
                raise RobotSpecError(f"{where} {text!r}: write tcp://host:port (port 1–65535)")
            return RobotSpec(text, SpecKind.TCP)
        if scheme not in _PYSERIAL_SCHEMES:
            raise RobotSpecError(f"{where} {text!r}: unknown scheme {scheme}://; give {_FORMS}")
        if scheme != "loop" and not rest:
            raise RobotSpecError(f"{where} {text!r}: nothing after {scheme}://")
        return RobotSpec(text, SpecKind.URL)
    if _DEVICE.fullmatch(text) is None:
        raise RobotSpecError(f"{where} {text!r} is not {_FORMS}")
    return RobotSpec(text, SpecKind.SERIAL)
