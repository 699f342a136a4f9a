"""The real-time ``JOG`` command [DOC S1 p.48–49 §5.2.59]: build it and read it.

Format ``JOG<mode>;<reserve 00>;<- axis mask>;<+ axis mask>;<inch>``, every field 2-digit
hex, the **minus mask before the plus mask** (S1 and S17; bborrell's reversed order is
wrong). Bit 0 is X/J1 … bit 5 C/J6, bit 6 L1/J7, bit 7 L2/J8. The controller stops the jog by
itself when no JOG arrives for about 140 ms, so callers re-send it while the key is held.

>>> Jog(JogMode.XYZ, positive=axis_mask(0)).command
'JOG01;00;00;01;00'
>>> Jog.parse("JOG00;00;02;00;00")
Jog(mode=<JogMode.JOINT: 0>, negative=2, positive=0, inch=<JogInch.OFF: 0>)
"""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass
from typing import Final

from melfa.protocol.errors import LocalProtocolError, RemoteProtocolError

JOG_WATCHDOG_S: Final = 0.140
"""The controller stops a jog not renewed within about this long [DOC S1 §5.2.59]."""


class JogMode(enum.IntEnum):
    """Jog coordinate system."""

    JOINT = 0x00
    XYZ = 0x01
    TOOL = 0x02
    XYZ3 = 0x04  # 3-axis XYZ
    CYLINDRICAL = 0x05


class JogInch(enum.IntEnum):
    """Inching (small fixed steps) instead of continuous jog."""

    OFF = 0x00
    HIGH = 0x01
    LOW = 0x02


def axis_mask(axis: int) -> int:
    """Mask bit of an axis, 0-based (0 = X/J1 … 7 = L2/J8)."""
    if not 0 <= axis <= 7:
        raise LocalProtocolError(f"jog axis {axis} is outside 0–7")
    return 1 << axis


@dataclass(frozen=True)
class Jog:
    """One JOG command. All-zero masks mean "stand still" (an explicit stop)."""

    mode: JogMode
    negative: int = 0
    positive: int = 0
    inch: JogInch = JogInch.OFF

    def __post_init__(self) -> None:
        for name, mask in (("negative", self.negative), ("positive", self.positive)):
            if not 0 <= mask <= 0xFF:
                raise LocalProtocolError(f"jog {name} mask {mask} is outside 00–FF")
        if self.negative & self.positive:
            raise LocalProtocolError(
                f"jog asks for both directions on axes {self.negative & self.positive:#04x}"
            )

    @classmethod
    def axis(cls, mode: JogMode, axis: int, direction: int, inch: JogInch = JogInch.OFF) -> Jog:
        """Jog one axis (0-based) in ``direction`` +1 or -1."""
        if direction not in (1, -1):
            raise LocalProtocolError(f"jog direction {direction} is not +1 or -1")
        mask = axis_mask(axis)
        return cls(mode, mask if direction < 0 else 0, mask if direction > 0 else 0, inch)

    @property
    def command(self) -> str:
        """Command text without the ``<robot>;<slot>;`` prefix."""
        return (
            f"JOG{int(self.mode):02X};00;{self.negative:02X};{self.positive:02X};"
            f"{int(self.inch):02X}"
        )

    @classmethod
    def parse(cls, command: str) -> Jog:
        """Read a JOG command (simulator side); `RemoteProtocolError` (6010) if malformed."""
        match = re.fullmatch(
            r"JOG([0-9A-Fa-f]{2});([0-9A-Fa-f]{2});([0-9A-Fa-f]{2});([0-9A-Fa-f]{2});"
            r"([0-9A-Fa-f]{2})",
            command.strip(),
        )
        if match is None:
            raise RemoteProtocolError(f"malformed JOG command {command[:40]!r}", error_number=6010)
        try:
            return cls(
                JogMode(int(match.group(1), 16)),
                int(match.group(3), 16),
                int(match.group(4), 16),
                JogInch(int(match.group(5), 16)),
            )
        except (ValueError, LocalProtocolError) as exc:
            raise RemoteProtocolError(f"bad JOG command: {exc}", error_number=6010) from None
