"""Programs: memory and the edit slot (LOAD/EMDAT/SAVE/LIST…/PDIR/FDEL) and the task slots
(PRGLOAD/RUN/RSTPRG/SLOTINIT).

Programs are written through the edit slot: `LOAD=<name>` opens a copy, `EMDAT`/`EDATA`
change it (each line checked as it comes [DOC S1 §5.2.7–5.2.8]), `SAVE` replaces the stored
program, `NEW` throws the copy away. A slot runs a stored program through its runner.
"""

from __future__ import annotations

import datetime as dt
import re

from melfa.protocol.error_table import NOT_PSA, ORIGIN_NOT_SET
from melfa.protocol.messages import VT, EditRefused, Ok, Refused, Reply, Request
from melfa.sim import errors as err
from melfa.sim.core import ControllerCore, Handler, Slot, SlotState
from melfa.sim.runner import StatementExecutor
from melfa.sim.store import EditBuffer, EditError, classify_item, program_name
from melfa.sim.syntax import first_syntax_error

LISTL_MAX_ANSWER = 240
"""Largest LISTL answer body before "more follows" [GUESS: the real split point is unknown]."""

# ----------------------------------------------------------------------------- slots


def prgload(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    name = program_name(arg)
    slot = c.slot(req)
    if slot.state is not SlotState.IDLE:
        # [DOC S1 §4.6] refused while a program runs or is paused: SLOTINIT first.
        return Refused(err.PROGRAM_RUNNING)
    if name is None or name not in c.store:
        return Refused(err.PROGRAM_NOT_FOUND)
    c.select(slot, name)
    return Ok()


def run(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    slot = c.slot(req)
    name_part, _, mode = arg.partition(";")
    cycle = mode.strip() != "0"
    if slot.state is SlotState.RUNNING:
        return Refused(err.PROGRAM_RUNNING)
    if c.origin_lost(now):
        return Refused(ORIGIN_NOT_SET)
    if c.alarm is not None:
        return Refused(err.DURING_ERROR)
    if c.moving:
        return Refused(err.BUSY)
    if name_part.strip():
        name = program_name(name_part)
        if name is None or name not in c.store:
            return Refused(err.PROGRAM_NOT_FOUND)
        if c.edit is not None and c.edit.name == name:
            return Refused(err.PROGRAM_BEING_EDITED)
        if slot.state is SlotState.PAUSED and slot.program == name:
            slot.cycle = cycle
            c.resume_slot(slot, now)
            return Ok()
        if slot.state is SlotState.PAUSED:
            # [TRACE K9b-RAW] a program paused mid-way holds the slot: another cannot be
            # selected ("not PSA") until SLOTINIT.
            return Refused(NOT_PSA)
        c.select(slot, name)
    elif slot.program is None or slot.runner is None:
        return Refused(err.PROGRAM_NOT_FOUND)
    elif slot.state is SlotState.PAUSED:
        c.resume_slot(slot, now)
        return Ok()
    assert slot.runner is not None
    slot.cycle = cycle
    slot.runner.start(now, cycle=cycle)
    # A program starts executing at the RUN, not at the next request.
    c.run_slot(slot, now)
    return Ok()


_TRAILING_COMMA = re.compile(r",\s*\)")


def hot(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    """``HOT<program>[.MB4];<variable>=<value>``: write a variable of a program that runs
    (or is paused) in a slot, while it runs [R-protocol manual; ctu-mitsubishi sends
    ``HOTMoveit;J1=(0.00,…,0.00,)`` to a real RV-6S: the trailing comma is accepted].
    Refused with 4140 when no slot holds the program."""
    target, _, assignment = arg.partition(";")
    name = program_name(target.strip().upper().removesuffix(".MB4"))
    if name is None or "=" not in assignment:
        return Refused(err.ILLEGAL_COMMAND)
    slot = next(
        (s for s in c.slots.values() if s.program == name and s.state is not SlotState.IDLE),
        None,
    )
    if slot is None or not isinstance(slot.runner, StatementExecutor):
        return Refused(err.PROGRAM_NOT_FOUND)
    slot.runner.execute(_TRAILING_COMMA.sub(")", assignment.strip()), now)
    return Ok()


def rstprg(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    slot = c.slot(req)
    if slot.state is SlotState.RUNNING:
        return Refused(err.PROGRAM_RUNNING)
    c.reset_slot(slot)
    return Ok()


def slotinit(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.program_running:
        return Refused(err.PROGRAM_RUNNING)
    for slot in c.slots.values():
        c.reset_slot(slot)
    return Ok()


# ---------------------------------------------------------------------------- editing


def load(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    name = program_name(arg)
    if name is None:
        return Refused(err.BAD_PROGRAM_NAME)
    if c.busy_with(name):
        return Refused(err.PROGRAM_RUNNING)
    c.edit = EditBuffer.of(name, c.store.get(name))
    c.listi_cursor = 0
    c.listp_cursor = 0
    return Ok()


def new(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    c.edit = None
    return Ok()


def eclr(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.edit is not None:
        c.edit.clear()
    return Ok()


def emdat(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.edit is None:
        return Refused(err.NOT_EDITING)
    # [DOC S1 p.8] items are separated by VT; a trailing VT leaves an empty item.
    staged = EditBuffer(c.edit.name, dict(c.edit.lines), dict(c.edit.positions))
    for index, raw in enumerate(arg.split(VT), start=1):
        if not raw.strip():
            continue
        try:
            item = classify_item(raw)
            if c.config.check_syntax_on_emdat and item.text is not None:
                _check_step(item.text, raw)
        except EditError as bad:
            return EditRefused(bad.number, index, bad.column)
        staged.apply(item)
    # A refused batch changes nothing [GUESS: all-or-nothing per EMDAT].
    c.edit = staged
    return Ok()


def edata(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.edit is None:
        return Refused(err.NOT_EDITING)
    try:
        item = classify_item(arg)
        if c.config.check_syntax_on_emdat and item.text is not None:
            _check_step(item.text, arg)
    except EditError as bad:
        return EditRefused(bad.number, None, bad.column)
    c.edit.apply(item)
    return Ok()


def _check_step(text: str, raw: str) -> None:
    found = first_syntax_error(text)
    if found is not None:
        number, column = found
        offset = len(raw) - len(raw.lstrip(" "))
        raise EditError(number, offset + column, f"syntax error in {text!r}")


def save(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    if c.edit is None:
        # [TRACE §4.2 item 6] the thesis sends SAVE with nothing open before deleting.
        return Ok()
    found = first_syntax_error(c.edit.text())
    if found is not None:
        # The old program stays; the edit slot stays open for corrections.
        return Refused(found[0])
    when = c.config.clock_origin + dt.timedelta(seconds=now)
    c.store.put(c.edit.to_program(when))
    name = c.edit.name
    c.edit = None
    for slot in c.slots.values():
        if slot.program == name and slot.state is SlotState.IDLE:
            c.select(slot, name)
    return Ok()


# ---------------------------------------------------------------------------- listings


def _listing_program(c: ControllerCore, req: Request) -> EditBuffer | None:
    if c.edit is not None:
        return c.edit
    program = c.store.get(c.slot(req).program or "")
    return EditBuffer.of(program.name, program) if program is not None else None


def listl(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # `LISTL<pos>`: `QoK<line>[VT<line>…];<count>;<1 more follows / 0 end>`.
    buffer = _listing_program(c, req)
    lines = [] if buffer is None else [buffer.lines[n] for n in sorted(buffer.lines)]
    start = arg.strip().lstrip("<").upper()
    if start and start != "TOP":
        if not start.isdigit():
            return Refused(err.ILLEGAL_COMMAND)
        lines = [ln for ln in lines if int(ln.split(" ", 1)[0]) >= int(start)]
    chosen: list[str] = []
    size = 0
    for line in lines:
        if chosen and size + len(line) + 1 > LISTL_MAX_ANSWER:
            break
        chosen.append(line)
        size += len(line) + 1
    more = "1" if len(chosen) < len(lines) else "0"
    return Ok(f"{VT.join(chosen)};{len(chosen)};{more}")


def listi(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    buffer = _listing_program(c, req)
    numbers = [] if buffer is None else sorted(buffer.lines)
    where = arg.strip().upper()
    if where == "TOP":
        c.listi_cursor = 0
    elif where == "+1":
        c.listi_cursor += 1
    elif where == "-1":
        c.listi_cursor = max(0, c.listi_cursor - 1)
    elif where.isdigit():
        wanted = int(where)
        c.listi_cursor = next((i for i, n in enumerate(numbers) if n >= wanted), len(numbers))
    else:
        return Refused(err.ILLEGAL_COMMAND)
    if buffer is None or not 0 <= c.listi_cursor < len(numbers):
        return Ok()
    return Ok(buffer.lines[numbers[c.listi_cursor]])


def listp(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    buffer = _listing_program(c, req)
    names = [] if buffer is None else list(buffer.positions)
    where = arg.strip().upper()
    if where == "TOP":
        c.listp_cursor = 0
    elif where == "+1":
        c.listp_cursor += 1
    elif where in names:
        c.listp_cursor = names.index(where)
    else:
        return Refused(err.VARIABLE_NOT_DEFINED)
    if buffer is None or not 0 <= c.listp_cursor < len(names):
        return Ok()
    return Ok(format_position(buffer.positions[names[c.listp_cursor]]))


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)")


def format_position(definition: str) -> str:
    """`P1=(400.13,0,644.62,180,0,180)(7,0)` -> `P1=(+400.13,+0.00,…)(7,0)` as LISTP shows it
    [DOC S1 example]; a value that is not a number is kept as written."""
    name, _, rest = definition.partition("=")
    values, _, flags = rest.strip().lstrip("(").partition(")")

    def one(text: str) -> str:
        text = text.strip()
        if not _NUMBER.fullmatch(text):
            return text
        return f"{float(text):+.2f}"

    body = ",".join(one(v) for v in values.split(","))
    return f"{name.strip().upper()}=({body}){flags.strip()}"


# --------------------------------------------------------------------------- directory


def pdir(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [TRACE S21] `PDIR<` (and TOP): first entry with count and free bytes;
    # `PDIRnn`: entry nn (1-based) without them; empty: `QoK;;;0;225536;;;;;;;`.
    where = arg.strip().upper()
    names = c.store.names()
    free = max(0, c.config.free_bytes - c.store.total_size())
    if where in ("<", "TOP", ""):
        if not names:
            return Ok(f";;;0;{free};;;;;;;")
        return Ok(_pdir_entry(c, names[0], f"{len(names)};{free};"))
    if not where.isdigit():
        return Refused(err.ILLEGAL_COMMAND)
    index = int(where)
    if not 1 <= index <= len(names):
        return Ok()
    return Ok(_pdir_entry(c, names[index - 1], ""))


def _pdir_entry(c: ControllerCore, name: str, middle: str) -> str:
    program = c.store.get(name)
    assert program is not None
    stamp = f"{program.saved_at:%y-%m-%d%H:%M:%S}"
    return (
        f"{program.file_name};{program.size()};{stamp};{middle}12;;"
        f"{len(program.lines)};{len(program.positions)};0;0;0;0"
    )


def fdel(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    name = program_name(arg)
    if name is None or name not in c.store:
        return Refused(err.PROGRAM_NOT_FOUND)
    if c.busy_with(name):
        return Refused(err.PROGRAM_RUNNING)
    c.store.delete(name)
    for slot in c.slots.values():
        if slot.program == name:
            _empty(slot)
    return Ok()


def _empty(slot: Slot) -> None:
    slot.program = None
    slot.runner = None


def fcheck(c: ControllerCore, arg: str, req: Request, now: float) -> Reply:
    # [DOC S1] `QoKN` = exists, `QoKF` = missing.
    name = program_name(arg)
    return Ok("N" if name is not None and name in c.store else "F")


HANDLERS: dict[str, Handler] = {
    "PRGLOAD=": prgload,
    "RUN": run,
    "HOT": hot,
    "RSTPRG": rstprg,
    "SLOTINIT": slotinit,
    "LOAD=": load,
    "NEW": new,
    "ECLR": eclr,
    "EMDAT": emdat,
    "EDATA": edata,
    "SAVE": save,
    "LISTL": listl,
    "LISTI": listi,
    "LISTP": listp,
    "PDIR": pdir,
    "FDEL": fdel,
    "FCHECK": fcheck,
}
