"""Program memory: write a program exactly or not at all, confirm it, read it back.

The LOAD…SAVE session of every upload [DOC S1 §5.2; TRACE K9b-READ, RT ToolBox]::

    [CNTLON SLOTINIT CNTLOFF]  NEW  LOAD=<prog>  [PRTVER…]  ECLR  EMDAT…  PARRLNG  SAVE  PDIR

- The slot is reset under operation rights first, as RT ToolBox and the thesis do.
- ``SAVE`` is sent only when every EMDAT was accepted *and* the pairing is proven sound by a
  request whose answer names itself (``PARRLNG`` → ``QoKRLNG;…``): if a stray or late reply
  had shifted the pairing, an EMDAT's reply (even a refusal of the last one) would arrive in
  its place, and the upload stops with NEW instead of saving a truncated program.
- After ``SAVE`` the directory entry (``PDIR``) must show the program with as many steps
  and positions as were sent; ``verify`` also reads every line back (``LISTL``; positions
  with ``LISTP`` only where the profile says the controller answers it).
- A lost or garbled ``SAVE`` answer is "outcome unknown": the channel resynchronises,
  ``PDIR`` says what the controller now holds; when it lists the program, or when its
  counts are empty or counted differently, `SavedNotConfirmed` says "saved, but not
  confirmed" rather than "failed".
"""

from __future__ import annotations

import contextlib
import re
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Protocol

from melfa.lang.plan import UploadItem, UploadPlan
from melfa.link import LinkError
from melfa.protocol import (
    REQUEST_LIMIT,
    VT,
    EditRefused,
    EmdatChunk,
    LocalProtocolError,
    Ok,
    ProgramEntry,
    RemoteProtocolError,
    Reply,
    chunk_emdat,
)
from melfa.protocol.error_table import PROGRAM_RUNNING
from melfa.robot.channel import Channel, StopOvertook
from melfa.robot.errors import ControllerError, RobotError, Stopped, UploadRefused
from melfa.robot.settings import RobotSettings

Progress = Callable[[int, int], None]
"""``progress(bytes_sent, bytes_total)`` during an upload."""

MAX_PDIR_ENTRIES = 64
"""Directory entries read while looking for the program (the CR2B holds far fewer)."""
MAX_LISTL_PAGES = 2000
"""Bound on LISTL pages during a read-back (each carries at least one line)."""


class SaveOutcomeUnknown(RobotError):
    """``SAVE`` was sent but its answer was lost; ``held`` is what PDIR showed afterwards."""

    def __init__(self, message: str, held: ProgramEntry | None) -> None:
        super().__init__(message)
        self.held = held


class SavedNotConfirmed(SaveOutcomeUnknown):
    """The controller saved (SAVE answered, or PDIR lists the program after a lost or
    garbled answer), but what it holds could not be matched with what was sent: PDIR's
    step/position fields are empty or count differently. Not a failure: say so plainly."""


class VerifyFailed(RobotError):
    """The read-back differs from what was sent."""


@dataclass(frozen=True)
class UploadReport:
    """What an upload sent, and what the controller was seen to hold afterwards."""

    items: int
    requests: int
    bytes_sent: int
    seconds: float
    held: ProgramEntry | None = None
    """The PDIR entry after SAVE (None when confirmation is off)."""
    verified: bool = False
    """True when every line was read back and matched (``verify``)."""
    unchecked: str | None = None
    """What ``verify`` could not read back, and why (positions without ``LISTP``)."""

    @property
    def confirmation(self) -> str:
        """One sentence on what the controller holds."""
        if self.held is None:
            return "not confirmed (confirm_save is off)"
        what = f"{self.held.lines} steps and {self.held.points} positions"
        checked = "read back line by line" if self.verified else "confirmed by PDIR"
        unchecked = f"; {self.unchecked}" if self.unchecked else ""
        return f"the controller holds {self.held.name}.MB4 with {what} ({checked}){unchecked}"


class Session(Protocol):
    """What the program-memory operations need of `melfa.robot.Robot`."""

    settings: RobotSettings
    channel: Channel
    pdir_hints: dict[str, int]
    handshaken: bool

    @property
    def edit_slot(self) -> int: ...

    def _call(
        self, command: str, *, slot: int | None = None, timeout: float | None = None
    ) -> Ok: ...

    def _send(
        self, command: str, slot: int | None = None, timeout: float | None = None
    ) -> Reply: ...

    def _raw(
        self,
        command: str,
        *,
        slot: int | None = None,
        timeout: float | None = None,
        rights: bool | None = None,
    ) -> Reply: ...

    def _note(self, reply: Reply) -> None: ...

    def _checkpoint(self, generation: int) -> None: ...

    def _error_message(self, number: int, wire: str | None = None) -> str: ...

    def _refusal(self, reply: Reply, command: str, *, fetch: bool = True) -> ControllerError: ...

    def _release_rights(self) -> None: ...


def reset_slot(session: Session) -> None:
    """``CNTLON`` ``SLOTINIT`` (``CNTLOFF`` when `release_rights_for_edit`): what RT ToolBox
    and the thesis send before writing, running and deleting [TRACE K9b-READ/DEL/RUN]."""
    if session.settings.slot_reset:
        session._call("SLOTINIT")


def find_program(session: Session, name: str) -> ProgramEntry | None:
    """The PDIR entry of program ``name``: ``PDIR<`` (first entry and count), then
    ``PDIR02``… as RT ToolBox reads the directory [TRACE K9b-READ]. Where it was found last
    time is tried first (one request after a re-upload); a miss falls back to the scan."""
    hint = session.pdir_hints.get(name.upper())
    if hint is not None and hint > 1:
        entry = ProgramEntry.parse(session._call(f"PDIR{hint:02d}").answer)
        if entry.name.upper() == name.upper():
            return entry
    return _scan(session, name)


def _scan(session: Session, name: str) -> ProgramEntry | None:
    first = ProgramEntry.parse(session._call("PDIR<").answer)
    if first.empty:
        return None
    if first.name.upper() == name.upper():
        return first
    count = min(first.count or MAX_PDIR_ENTRIES, MAX_PDIR_ENTRIES)
    for index in range(2, count + 1):
        entry = ProgramEntry.parse(session._call(f"PDIR{index:02d}").answer)
        if entry.empty:
            return None
        if entry.name.upper() == name.upper():
            session.pdir_hints[name.upper()] = index
            return entry
    return None


def write_program(
    session: Session,
    prepared: UploadPlan,
    generation: int,
    progress: Progress | None,
    *,
    clear: bool,
    verify: bool = False,
) -> UploadReport:
    """The LOAD…SAVE session shared by every upload; see the module doc."""
    settings = session.settings
    channel = session.channel
    items = list(prepared.items)
    started = time.monotonic()
    sent_before = channel.sent_bytes
    chunks = _chunks(session, items)
    total = sum(len(c.request.to_bytes()) for c in chunks)
    if progress is not None:
        progress(0, total)
    program = settings.program
    reset_slot(session)
    if settings.release_rights_for_edit:
        session._release_rights()
    session._call("NEW")
    try:
        session._call(f"LOAD={program}")
    except ControllerError as exc:
        if exc.number != PROGRAM_RUNNING:
            raise
        session._call("RSTPRG")  # a paused run holds the program: release it, retry
        session._call(f"LOAD={program}")
    save_sent = False
    try:
        if settings.prtver_handshakes and not session.handshaken:
            _handshakes(session)
            session.handshaken = True
        if clear:
            session._call("ECLR")
        _send_chunks(session, chunks, items, generation, progress, total)
        session._checkpoint(generation)
        _fence(session)
        save_sent = True
        session._call("SAVE", timeout=settings.save_timeout)
    except BaseException as exc:
        if save_sent or not isinstance(exc, LinkError):
            with contextlib.suppress(Exception):
                session._send("NEW")  # close without saving: the old program stays
        # A link failure before SAVE fails at once: nothing was saved, and the next
        # upload's own NEW discards the open edit (waiting out a resync and a NEW on a
        # dead line only delays the answer).
        if save_sent and isinstance(exc, LinkError | RemoteProtocolError):
            # Lost or garbled (a flipped bit): the controller may have saved; PDIR tells.
            raise _lost_save(session, prepared, clear, exc) from exc
        raise
    held = None
    if settings.confirm_save:
        held = _confirm(session, prepared, clear)
    verified = False
    unchecked = None
    if verify:
        unchecked = read_back(session, prepared, clear)
        verified = True
    return UploadReport(
        len(items),
        len(chunks),
        channel.sent_bytes - sent_before,
        time.monotonic() - started,
        held,
        verified,
        unchecked,
    )


def _handshakes(session: Session) -> None:
    """[GUESS] ``PRTVERLISTL``/``PRTVEREMDAT`` as the thesis sent them, once per session
    (a protocol-version handshake); a refusal is fine (they are undocumented and the
    upload does not depend on them)."""
    for command in ("PRTVERLISTL", "PRTVEREMDAT"):
        reply = session._raw(command)
        if not isinstance(reply, Ok):
            return


def _fence(session: Session) -> None:
    """Prove the pairing sound before SAVE: ``PARRLNG`` must be answered ``RLNG;…``."""
    reply = session._send("PARRLNG")
    if not (isinstance(reply, Ok) and reply.answer.upper().startswith("RLNG;")):
        raise RobotError(
            f"the controller answered {reply!r} to PARRLNG: replies are out of step, "
            "so nothing was saved"
        )


def _send_chunks(
    session: Session,
    chunks: list[EmdatChunk],
    items: list[UploadItem],
    generation: int,
    progress: Progress | None,
    total: int,
) -> None:
    stops = session.channel.stops_sent  # first, then the checkpoint: no STOP slips between
    session._checkpoint(generation)
    replies = session.channel.pipeline(
        (c.request for c in chunks), session.settings.emdat_window, stops_seen=stops
    )
    refused: tuple[Reply, EmdatChunk] | None = None
    sent = 0
    try:
        for chunk, reply in zip(chunks, replies, strict=True):
            session._note(reply)
            if not isinstance(reply, Ok):
                refused = (reply, chunk)
                break
            sent += len(chunk.request.to_bytes())
            if progress is not None:
                progress(sent, total)
            session._checkpoint(generation)
    except StopOvertook:
        raise Stopped("stopped by request") from None
    finally:
        replies.close()  # reads (and drops) replies still in flight
    if refused is not None:
        raise _upload_refusal(session, refused[0], refused[1], items)


def _expected(prepared: UploadPlan, clear: bool) -> tuple[int | None, int | None]:
    steps = prepared.program_lines if clear else None
    points = prepared.point_count if clear else None
    return steps, points


def counts_match(held: ProgramEntry, steps: int | None, points: int | None) -> bool | None:
    """Whether PDIR's counts show what was sent: True, False, or None when PDIR's step or
    position field is empty (nothing to compare). Firmware that counts the positions in
    the steps (``lines`` = steps + positions) matches too."""
    if (steps is not None and held.lines is None) or (points is not None and held.points is None):
        return None
    if steps is not None and points is not None and held.lines == steps + points:
        return True
    return (steps is None or held.lines == steps) and (points is None or held.points == points)


def _confirm(session: Session, prepared: UploadPlan, clear: bool) -> ProgramEntry:
    name = session.settings.program
    held = find_program(session, name)
    if held is None:
        raise RobotError(
            f"SAVE was answered, but PDIR does not list program {name}: the controller "
            "holds no copy of it"
        )
    steps, points = _expected(prepared, clear)
    if session.settings.confirm_counts and not counts_match(held, steps, points):
        raise SavedNotConfirmed(
            f"saved, but not confirmed: SAVE was answered and PDIR lists {name}.MB4 "
            f"({held.stamp}), but {_counts(held)} where {steps} steps and {points} positions "
            "were sent (upload again with --verify to read the steps back, or run `melfa "
            "doctor --probe-upload` to learn how this controller counts)",
            held,
        )
    return held


def _counts(held: ProgramEntry) -> str:
    if held.lines is None or held.points is None:
        return "it shows no step or position counts"
    return f"it shows {held.lines} steps and {held.points} positions"


def _lost_save(
    session: Session, prepared: UploadPlan, clear: bool, cause: BaseException
) -> SaveOutcomeUnknown:
    name = session.settings.program
    what = "garbled" if isinstance(cause, RemoteProtocolError) else "lost"
    try:
        session.channel.resync()
        held = find_program(session, name)
    except (LinkError, RobotError, LocalProtocolError, RemoteProtocolError) as exc:
        return SaveOutcomeUnknown(
            f"SAVE's answer was {what}: outcome unknown, and the controller could not be "
            f"asked what it holds ({exc})",
            None,
        )
    if held is None:
        return SaveOutcomeUnknown(
            f"SAVE's answer was {what}: outcome unknown. PDIR lists no program {name}: "
            "it was not saved",
            None,
        )
    steps, points = _expected(prepared, clear)
    match = counts_match(held, steps, points)
    if match is False:
        return SaveOutcomeUnknown(
            f"SAVE's answer was {what}: outcome unknown. The controller now holds {name}.MB4 "
            f"({held.stamp}) with {held.lines} steps and {held.points} positions, not what "
            f"was sent ({steps} and {points}): the old program is probably still there",
            held,
        )
    counted = "as many steps and positions as were sent" if match else _counts(held)
    return SavedNotConfirmed(
        f"saved, but not confirmed: SAVE's answer was {what}; PDIR lists {name}.MB4 "
        f"({held.stamp}) and {counted}, so it was probably saved (upload again with "
        "--verify to be sure)",
        held,
    )


# ---------------------------------------------------------------------- read-back

_SPACES = re.compile(r"\s+")


def _same_line(a: str, b: str) -> bool:
    return _SPACES.sub(" ", a.strip()).upper() == _SPACES.sub(" ", b.strip()).upper()


def _point_values(text: str) -> tuple[str, tuple[float, ...], str]:
    name, _, rest = text.partition("=")
    body, _, flags = rest.strip().lstrip("(").partition(")")
    values = []
    for part in body.split(","):
        with contextlib.suppress(ValueError):
            values.append(float(part))
    return name.strip().upper(), tuple(values), flags.strip()


def _same_point(a: str, b: str) -> bool:
    na, va, fa = _point_values(a)
    nb, vb, fb = _point_values(b)
    close = len(va) == len(vb) and all(abs(x - y) <= 0.006 for x, y in zip(va, vb, strict=True))
    return na == nb and close and fa.replace(" ", "") == fb.replace(" ", "")


def read_lines(session: Session) -> Iterator[str]:
    """Every step of the open program: ``LISTL<`` then ``LISTL<n`` from the next line
    number, at the edit slot, until the answer says no more follow (``;0``)."""
    start = ""
    for _ in range(MAX_LISTL_PAGES):
        answer = session._call(f"LISTL<{start}", slot=session.edit_slot).answer
        body, _, tail = answer.rpartition(";")
        body, _, _count = body.rpartition(";")
        lines = [line for line in body.split(VT) if line]
        yield from lines
        if tail != "1" or not lines:
            return
        number = lines[-1].split(" ", 1)[0]
        if not number.isdigit():
            return
        start = str(int(number) + 1)


def read_points(session: Session) -> Iterator[str]:
    """Every position of the open program: ``LISTPTOP`` then ``LISTP+1`` until empty."""
    answer = session._call("LISTPTOP", slot=session.edit_slot).answer
    for _ in range(MAX_LISTL_PAGES):
        if not answer:
            return
        yield answer
        answer = session._call("LISTP+1", slot=session.edit_slot).answer


def read_back(session: Session, prepared: UploadPlan, clear: bool) -> str | None:
    """Open the saved program and compare every line (``LISTL``, which real clients send)
    and, where the profile says the controller answers ``LISTP`` (`listp_answered`: no
    real controller was recorded answering it), every position with what was sent.
    Returns what could not be read back, or None."""
    session._call("NEW")
    session._call(f"LOAD={session.settings.program}")
    listp = session.settings.listp_answered
    try:
        lines = list(read_lines(session))
        points = list(read_points(session)) if listp else []
    finally:
        with contextlib.suppress(Exception):
            session._call("NEW")
    sent_lines, sent_points = prepared.program_texts, prepared.point_texts
    if clear or prepared.has_program:
        if len(lines) != len(sent_lines):
            raise VerifyFailed(f"read back {len(lines)} steps; {len(sent_lines)} were sent")
        for index, (got, sent) in enumerate(zip(lines, sent_lines, strict=True), start=1):
            if not _same_line(got, sent):
                raise VerifyFailed(f"step {index} reads back as {got!r}; {sent!r} was sent")
    if not listp:
        return (
            f"the {len(sent_points)} positions were counted by PDIR, not read back (this "
            "controller is not known to answer LISTP)"
            if sent_points
            else None
        )
    by_name = {_point_values(p)[0]: p for p in points}
    for sent in sent_points:
        name = _point_values(sent)[0]
        held = by_name.get(name)
        if held is None or not _same_point(held, sent):
            raise VerifyFailed(f"position {name} reads back as {held!r}; {sent!r} was sent")
    if clear and len(points) != len(sent_points):
        raise VerifyFailed(f"read back {len(points)} positions; {len(sent_points)} were sent")
    return None


# ------------------------------------------------------------------------ chunks


def _chunks(session: Session, items: list[UploadItem]) -> list[EmdatChunk]:
    slot = session.edit_slot
    robot = session.settings.robot
    prefix = len(f"{robot};{slot};EMDAT")
    for item in items:
        if len(item.text) > REQUEST_LIMIT - prefix:
            raise RobotError(
                f"{item.source} line {item.source_line} is {len(item.text)} characters; "
                f"one EMDAT request carries at most {REQUEST_LIMIT - prefix}"
            )
    try:
        return chunk_emdat([i.text for i in items], robot=robot, slot=slot)
    except LocalProtocolError as exc:
        raise RobotError(str(exc)) from None


def _upload_refusal(
    session: Session, reply: Reply, chunk: EmdatChunk, items: list[UploadItem]
) -> ControllerError:
    if isinstance(reply, EditRefused):
        index = chunk.line_index(reply.item or 1)
        item = items[min(index, len(items) - 1)]
        return UploadRefused(
            reply.error,
            session._error_message(reply.error, reply.code.wire),
            line=item.source_line,
            column=reply.column,
            text=item.text,
            alarm=reply.alarm,
            source=item.source,
        )
    return session._refusal(reply, "EMDAT")
