"""Line settings, with the 9600 8E2 CR default in exactly one place.

[DOC S5] factory parameters CBAU232 = 9600, CPRTY232 = 2 (even), CSTOP232 = 2, CTERM232 = 0
(CR); [CODE S6, S7, S9, S10, S19] all open 8 data bits. Checked when built (pyserial's
habit), and convertible to pyserial keyword arguments.

>>> LinkSettings().describe()
'9600 8E2, CR, timeout 3 s'
>>> LinkSettings(parity="N", stopbits=1).describe()
'9600 8N1, CR, timeout 3 s'
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Final

BAUDRATES: Final = (1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200)
"""Rates a CR2B can be configured for (CBAU232) and a bit more; S9 runs at 38400."""
BYTESIZES: Final = (7, 8)
PARITIES: Final = ("N", "E", "O")
STOPBITS: Final = (1, 2)
TERMINATORS: Final = {b"\r": "CR", b"\r\n": "CR LF", b"": "none", b"\x00": "NUL"}
"""CTERM232 0 = CR, 1 = CR LF [DOC S5]; Ethernet drivers use none (S11) or NUL (S12)."""

DEFAULT_TIMEOUT_S: Final = 3.0
"""Per-request reply deadline. The longest normal exchange (a 254-byte EMDAT plus SAVE
processing) is well under a second at 9600 baud; the S21 traces show ≤ 0.3 s round trips."""


@dataclass(frozen=True)
class LinkSettings:
    """How to talk on the line. Every field can be overridden from the CLI and the service."""

    baudrate: int = 9600
    bytesize: int = 8
    parity: str = "E"
    stopbits: int = 2
    terminator: bytes = b"\r"
    timeout: float = DEFAULT_TIMEOUT_S
    rtscts: bool = False  # [GUESS] protocol.md §1.1: no handshake needed with the standard cable

    def __post_init__(self) -> None:
        if self.baudrate not in BAUDRATES:
            raise ValueError(f"baud rate {self.baudrate} is not one of {BAUDRATES}")
        if self.bytesize not in BYTESIZES:
            raise ValueError(f"byte size {self.bytesize} is not 7 or 8")
        if self.parity not in PARITIES:
            raise ValueError(f"parity {self.parity!r} is not N, E or O")
        if self.stopbits not in STOPBITS:
            raise ValueError(f"stop bits {self.stopbits} is not 1 or 2")
        if self.terminator not in TERMINATORS:
            raise ValueError(f"terminator {self.terminator!r} is not CR, CR LF, NUL or none")
        if not self.timeout > 0:
            raise ValueError(f"timeout {self.timeout} must be > 0 seconds")

    @property
    def bits_per_char(self) -> int:
        """Start bit + data + parity + stop bits: 12 for 8E2 [DERIVED protocol.md §6.1]."""
        return 1 + self.bytesize + (0 if self.parity == "N" else 1) + self.stopbits

    @property
    def seconds_per_char(self) -> float:
        """Wire time of one character: 1.25 ms at 9600 8E2."""
        return self.bits_per_char / self.baudrate

    def pyserial_kwargs(self) -> dict[str, Any]:
        """Keyword arguments for `serial.Serial` / `serial.serial_for_url`."""
        return {
            "baudrate": self.baudrate,
            "bytesize": self.bytesize,
            "parity": self.parity,
            "stopbits": self.stopbits,
            "rtscts": self.rtscts,
        }

    def with_(self, **changes: Any) -> LinkSettings:
        """A copy with some fields changed (checked again)."""
        return replace(self, **changes)

    def describe(self) -> str:
        """``9600 8E2, CR, timeout 3 s``."""
        return (
            f"{self.baudrate} {self.bytesize}{self.parity}{self.stopbits}, "
            f"{TERMINATORS[self.terminator]}, timeout {self.timeout:g} s"
        )
