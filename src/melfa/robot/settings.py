"""Every choice the documents leave open, as one settings object with safe defaults.

Each field marked [GUESS] comes from protocol.md's open list (§8); flip it once the real
CR2B-574 has been tried.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass


class HandMethod(enum.Enum):
    """How `Robot.hand` opens and closes a hand."""

    EXEC = "exec"  # EXECHOPEN n / EXECHCLOSE n: unambiguous [CODE S18], needs rights
    HND = "hnd"  # HNDON n / HNDOFF n [DOC S1 §5.2.56]; polarity is a [GUESS]


class JogMethod(enum.Enum):
    """How `Robot.jog` moves."""

    AUTO = "auto"  # try JOG; fall back to step moves if it is refused, remember the choice
    JOG = "jog"  # real-time JOG only [DOC S1 §5.2.59]
    STEP = "step"  # incremental EXEC moves only (the thesis's method)


@dataclass(frozen=True)
class RobotSettings:
    """Options of the robot client (defaults in brackets are the source of the choice)."""

    client_name: str = "MELFA"
    """``OPEN=<name>``; any name works [DOC S1; S6 NARCUSR, S21 TOOLBOX]."""
    robot: int = 1
    slot: int = 1
    """Task slot of the user program [S7: slot 1]."""
    program: str = "1"
    """Program name in that slot [S7: program "1"]."""
    edit_slot: int | None = None
    """Slot for EMDAT; None = TASKMAX+1 from the OPEN banner, 9 if it has none [DOC S1]."""
    stop_slot: int = 1
    """``1;1;STOP`` is the form real serial clients send [TRACE; CODE S6/S7]; 0 gives the
    manual's all-slots ``1;0;STOP`` [CODE S12, S18], never seen on a serial line."""
    slot_reset: bool = True
    """``SLOTINIT`` under operation rights before load, run (unless resuming) and delete,
    as RT ToolBox and the thesis do [TRACE K9b-READ/RUN/DEL; CODE S7]."""
    release_rights_for_edit: bool = True
    """[GUESS] ``CNTLOFF`` after the slot reset, before NEW/LOAD/EMDAT/SAVE, as RT ToolBox
    does; whether editing works while holding the rights is unconfirmed."""
    confirm_save: bool = True
    """After SAVE, read the directory (``PDIR``) and insist the program is listed."""
    confirm_counts: bool = True
    """[GUESS from TRACE] PDIR's 8th/9th fields are the step and position counts (they
    match every upload on record); the confirmation compares them with what was sent.
    `melfa doctor --probe-upload` checks this on the real controller."""
    listp_answered: bool = False
    """Whether the controller answers ``LISTP`` (positions read back by ``--verify``). No
    real controller was recorded answering it; `melfa doctor --probe-upload` finds out."""
    prtver_handshakes: bool = True
    """[GUESS §3.8] send PRTVERLISTL / PRTVEREMDAT after LOAD, as the thesis did on this
    controller family, once per session (a version handshake); a refusal is tolerated.
    Undocumented; `melfa doctor` probes them."""
    clear_with_eclr: bool = True
    """Clear the old program with ECLR after LOAD [DOC S1 §5.2; TRACE S21 RT ToolBox].
    ECLR clears steps *and* positions: `upload_program` replaces the whole program."""
    hand: HandMethod = HandMethod.EXEC
    hnd_on_opens: bool = True
    """[GUESS §3.6, §8.8] with `HandMethod.HND`: True = HNDON opens the hand."""
    jog: JogMethod = JogMethod.AUTO
    """[GUESS §3.9, §8.12] whether the CR2B accepts JOG over RS-232 in AUTO (Ext.)."""
    jog_step_mm: float = 10.0
    """Step-jog distance in mm (the thesis used 20 mm: TOOL_INCREMENT 0.02 m)."""
    jog_step_deg: float = 2.0
    """Step-jog angle in degrees for joints and A/B/C."""
    fetch_error_text: bool = True
    """After a refusal, ask ``ERRORMES<n>`` for the controller's own text (one round trip)."""
    cycle_mode: bool = True
    """``RUN<prog>;1``: run once (cycle) rather than repeat [S7]."""
    emdat_window: int = 1
    """[GUESS] EMDAT requests in flight at once. 1 = strictly one request, one reply, as
    every public driver does. 2 sends the next chunk while the controller still processes
    the previous one, hiding its ~0.1 s latency per chunk (bench/bench_link.py); it relies
    on the controller buffering a whole request received while busy. Safe on failure
    either way: a refused chunk means NEW, so nothing is saved."""
    save_timeout: float = 10.0
    """[GUESS] SAVE writes program memory; allow it longer than the link's request timeout."""

    def __post_init__(self) -> None:
        if not self.client_name or not self.client_name.isascii() or ";" in self.client_name:
            raise ValueError(f"client name {self.client_name!r} must be ASCII without ';'")
        if not self.program or not self.program.isalnum():
            raise ValueError(f"program name {self.program!r} must be letters and digits")
        if not 1 <= self.emdat_window <= 4:
            raise ValueError(f"emdat_window {self.emdat_window} is not 1–4")
        if self.jog_step_mm <= 0 or self.jog_step_deg <= 0:
            raise ValueError("jog steps must be positive")
