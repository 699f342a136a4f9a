"""Everything about the virtual controller that the documents leave open.

Each field that protocol.md marks [GUESS] is a named, configurable value here, so a test (or
a user who has measured the real CR2B-574) can flip it without touching the controller logic.
The defaults are what the public traces and drivers suggest.
"""

from __future__ import annotations

import datetime as dt
import enum
import os
from dataclasses import dataclass, field

# --- timing --------------------------------------------------------------------------------
from melfa.protocol.error_table import COMMAND_TOO_LONG
from melfa.protocol.jog import JOG_WATCHDOG_S  # the one home of the ~140 ms watchdog

DEFAULT_REPLY_LATENCY_S = 0.1
"""Controller processing time added by the servers before a reply (not by the core).
prior-art.md §5: the S21 traces show about 100–150 ms on top of the line time."""

SECONDS_PER_CHAR_9600_8E2 = 12 / 9600
"""[DERIVED protocol.md §6.1] 8E2 = 12 bits a character: 1.25 ms per character at 9600 baud."""

# --- wire limits ---------------------------------------------------------------------------

MAX_COMMAND_BYTES = 255
"""[DOC S1 p.6 §3.1] Maximum command size; the terminator is not counted [GUESS §2.1]."""

MAX_STEP_CHARS = 127
"""[melfa-basic-iv.md §1] A step holds at most 127 characters (L4210)."""

MAX_LINE_NUMBER = 32767
"""[melfa-basic-iv.md §1] Line numbers 1…32767 (L4420)."""


@dataclass(frozen=True, slots=True)
class Banner:
    """The OPEN reply fields [DOC S1 §3.1; TRACE K4a-CR2B, K9b]. Defaults follow the CR2B
    handshake on record (RV-3SB, `Ver.K4a`) with the RV-6S as robot; the copyright field names
    the simulator so a client can tell."""

    xyz_axes: str = "3F"
    joint_axes: str = "3F"
    default_flags: str = "7,0"
    jog_speeds: str = "3,5,A,1E,32,46,64"
    program_ext: str = "MB4"
    parameter_ext: str = "PRM"
    robot_type: str = "RV-6S"
    controller: str = "CRn-5xx"
    maker: str = "MELFA"
    date: str = "05-07-14"  # [TRACE K4a-CR2B] a CR2B's; the lab's CR2B-574's is unknown
    version: str = "Ver.K4a"  # [TRACE K4a-CR2B] a CR2B's firmware; the lab's is unknown
    language: str = "ENG"
    copyright: str = "MELFA VIRTUAL CONTROLLER (SIMULATED CR2B-574)"
    robot_info: str = "1"
    serial_no: str = "1"
    taskmax: int = 8  # [DOC S1] TASKMAX default 8, so the edit slot is 9

    def body(self) -> str:
        """The answer text after `QoK`, trailing `;` included as in the traces."""
        fields = (
            self.xyz_axes,
            self.joint_axes,
            self.default_flags,
            self.jog_speeds,
            self.program_ext,
            self.parameter_ext,
            self.robot_type,
            self.controller,
            self.maker,
            self.date,
            self.version,
            self.language,
            self.copyright,
            self.robot_info,
            self.serial_no,
            str(self.taskmax),
        )
        return ";".join(fields) + ";"


STRICT_ENV = "MELFA_SIM_STRICT"
"""`1`: every simulator created without an explicit `strict` is strict (`--robot sim`, the
web server's simulators, `melfa sim`): rehearse against what the real controller was seen
to answer. The test suite runs this way."""


def strict_by_default() -> bool:
    """Whether `$MELFA_SIM_STRICT` asks for strict simulators."""
    return os.environ.get(STRICT_ENV, "").strip() not in ("", "0")


class KeySwitch(enum.Enum):
    """The controller's MODE key [DOC S5 §4]. Only AUTO (Ext.) lets a computer on RS-232
    operate the robot; in TEACH the teaching pendant, in AUTO (Op.) the operation panel holds
    the operation rights."""

    TEACH = "teach"
    AUTO_OP = "auto-op"
    AUTO_EXT = "auto-ext"

    @property
    def label(self) -> str:
        """As the controller's panel writes it: `TEACH`, `AUTO (Op.)`, `AUTO (Ext.)`."""
        return {"teach": "TEACH", "auto-op": "AUTO (Op.)", "auto-ext": "AUTO (Ext.)"}[self.value]


class Terminator(enum.Enum):
    """What ends the controller's replies: its ``CTERM232`` parameter [DOC S5], 0 = CR
    (factory setting, every recorded reply [TRACE K9b-RAW]), 1 = CR LF (what ctu-mitsubishi's
    ``readline()`` needs to return at once; its lab must have had it)."""

    CR = "0"
    CRLF = "1"

    @property
    def wire(self) -> bytes:
        """The bytes after each reply."""
        return b"\r\n" if self is Terminator.CRLF else b"\r"


@dataclass(frozen=True, slots=True)
class SimConfig:
    """Options of the virtual controller. Every [GUESS] of protocol.md that changes what a
    client sees is a field here."""

    banner: Banner = field(default_factory=Banner)

    jog_supported: bool = True
    """[GUESS §3.9, §8.12] Whether CR2B firmware accepts `JOG` over RS-232 in AUTO (Ext.).
    False answers every JOG with L2030 so the client's step-jog fallback can be tested."""

    jog_watchdog_s: float = JOG_WATCHDOG_S

    exec_needs_program: bool = False
    """[GUESS §3.4, §8.7] Whether EXEC needs a program loaded in the slot (S6 loads an empty
    "COSIROP" first). When True, EXEC without PRGLOAD/RUN answers L4140."""

    hand_on_opens: bool = True
    """[GUESS §3.6, §8.8] Which of HNDON/HNDOFF opens the hand: True = HNDON opens."""

    run_bit_while_exec_moves: bool = True
    """[GUESS] STATE/DSTATE bit 0x40 (RUN) is also set while an EXEC motion or a jog moves the
    arm; S6/S7 see EXEC motion as "running" (5640 "Cannot execute during RUN")."""

    rights_for_slot_reset: bool = False
    """[GUESS] Whether SLOTINIT and RSTPRG need the operation rights. The manual's `*` list
    does not name them; S9 sends SLOTINIT before CNTLON, the thesis sends RSTPRG after."""

    check_syntax_on_emdat: bool = True
    """[DOC S1 §5.2.7–5.2.8] EMDAT errors carry the bad item and character position, so the
    controller checks each line as it is entered. SAVE checks the whole program again."""

    too_long_error: int = COMMAND_TOO_LONG
    """[DOC S4] C6080 "Com mesg is too long" (L3270 is the other candidate) [GUESS which one]."""

    prtver_answer: str = "1"
    """[TRACE S21] `PRTVERVALS` → `QoK1`; [GUESS] the same for PRTVERLISTL / PRTVEREMDAT."""

    edit_slot: int = 9
    """[DOC S1] The edit slot is TASKMAX+1."""

    clock_origin: dt.datetime = dt.datetime(2024, 1, 1, 0, 0, 0)
    """Wall-clock time at `now == 0`, for dates in PDIR and ERRORLOG (the core has no clock)."""

    key: KeySwitch = KeySwitch.AUTO_EXT
    """Where the MODE key stands at power-on (`VirtualController.turn_key` turns it later).
    Outside AUTO (Ext.) `CNTLON` is accepted but every command that needs the operation
    rights, and SLOTINIT/RSTPRG, is refused with 6020 "The Operation is disable" [TRACE
    K9b-PROG: SLOTINIT -> QeR602000000 in TEACH after a QoK to CNTLON; GUESS for AUTO (Op.)]."""

    origin_set: bool = True
    """False: the origin (encoder data) is lost, as after a battery failure. Positions read
    `****` and RUN, EXEC and JOG raise L5150 "The origin has not been set" [TRACE K9b-C1/C4]."""

    nine_digit_errors: bool = True
    """Refusals carry the real controller's 9 digits (`QeR602000000`: number + 5 detail
    digits) [TRACE K9b]; False answers the manual's 4 digits (`QeR6020`) [DOC S1]."""

    strict: bool = field(default_factory=lambda: strict_by_default())
    """Refuse (6010, in the real form) every command no real controller was seen to answer:
    only commands with recorded answers or sent by real serial clients are served (the list:
    docs/simulator.md). Default: `$MELFA_SIM_STRICT` (the test suite sets it)."""

    open_required: bool = False
    """True: the manual's rule, 6010 to everything before ``OPEN=`` [DOC S1 §3.1]. False
    (default, what was seen): three real serial clients never send OPEN and worked
    (ctu-mitsubishi on an RV-6S, a CR1-571 client, an RV-1A client) [CLIENT, issue 24]."""

    cterm: Terminator = Terminator.CR
    """``CTERM232``: the reply terminator (requests may end in CR, LF, CR LF, NUL, or
    nothing at all on a pause, as the Robotics Library sends them over TCP)."""

    free_bytes: int = 225536
    """[TRACE S21] Free program memory shown by PDIR on an empty controller."""

    def __post_init__(self) -> None:
        if self.jog_watchdog_s <= 0:
            raise ValueError("jog_watchdog_s must be positive")
