"""The command table: one home for what each controller command needs and does.

Who reads it: the robot client (which commands need the operation rights), the virtual
controller (the same rule when it answers, and "strict" mode: refuse what no real controller
was seen to answer), ``melfa doctor`` (never send anything that moves, powers or writes), and
the docs. Evidence per command: `Evidence.TRACE` = a real controller's answer is recorded
(``tests/fixtures/real_traffic.py``), `Evidence.CLIENT` = real serial clients send it but no
answer is recorded, `Evidence.DOC` = the manual only.

Slot forms [DOC S1 §3.3.1; TRACE K9b]: ``1;1;`` a task slot, ``1;0;`` all slots (STOP),
``1;-1;`` what RT ToolBox sends for position reads, ``1;9;`` the edit slot (TASKMAX + 1).

>>> needs_rights("RUN1;1"), needs_rights("RUNSHOWOF;1"), needs_rights("JOGST"), needs_rights("STOP")
(True, True, False, False)
>>> lookup("EXECMOV P1").name, lookup("OVRD=50").name, lookup("OVRD").name
('EXEC', 'OVRD=', 'OVRD')
>>> lookup("PDIR<").kind is Kind.READ, lookup("SRVON").kind is Kind.POWER
(True, True)
"""

from __future__ import annotations

import enum
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Final

from melfa.protocol.messages import EditRefused, Ok, Reply, Request


class SlotForm(enum.Enum):
    """The ``<slot>`` field a command is sent with."""

    TASK = "1"  # a task slot: 1 … TASKMAX
    ALL = "0"  # every slot (STOP)
    CURRENT = "-1"  # RT ToolBox's position reads [TRACE K9b-PROG]
    EDIT = "9"  # the edit slot, TASKMAX + 1 (EMDAT, LISTL)


class Kind(enum.Enum):
    """What a command does, for callers that must not do some things (``melfa doctor``)."""

    SESSION = "session"  # OPEN, CLOSE, CNTLON/CNTLOFF, KEYWD
    READ = "read"  # reads state, positions, parameters, files: changes nothing
    STOP = "stop"  # STOP
    POWER = "power"  # servo, alarm reset
    SETTING = "setting"  # changes a setting of the controller (override)
    MOTION = "motion"  # anything that can move the arm: EXEC, JOG, RUN, hand
    PROGRAM = "program"  # selects / resets a task slot (no motion)
    EDIT = "edit"  # writes program memory or parameters


class Evidence(enum.Enum):
    """How sure we are the real controller answers the command."""

    TRACE = "trace"  # a real answer is recorded
    CLIENT = "client"  # real serial clients send it; no answer recorded
    DOC = "doc"  # the manual only


@dataclass(frozen=True)
class CommandSpec:
    """One command word (or prefix, for those with ``=`` arguments)."""

    name: str
    kind: Kind
    rights: bool = False
    """Needs the operation rights (``CNTLON``): the manual's ``*`` commands [DOC S1/S2
    §5.1], RSTALRM [DOC S5], and SLOTINIT/RSTPRG, which RT ToolBox and the thesis always
    send under rights [TRACE K9b-READ/DEL; CODE S7]."""
    slots: frozenset[SlotForm] = frozenset({SlotForm.TASK})
    exact: bool = False
    """Takes no argument (``STATE`` must not match ``STATEX``)."""
    evidence: Evidence = Evidence.DOC


_S = SlotForm
_TASK = frozenset({_S.TASK})
_POS = frozenset({_S.TASK, _S.CURRENT, _S.EDIT})  # 1;9;JPOSF: a real CR1-571 [issue 24]
_EDIT = frozenset({_S.TASK, _S.EDIT})


def _c(
    name: str,
    kind: Kind,
    evidence: Evidence = Evidence.DOC,
    *,
    rights: bool = False,
    slots: frozenset[SlotForm] = _TASK,
    exact: bool = False,
) -> CommandSpec:
    return CommandSpec(name, kind, rights, slots, exact, evidence)


T, C, D = Evidence.TRACE, Evidence.CLIENT, Evidence.DOC
_TABLE: tuple[CommandSpec, ...] = (
    # session
    _c("OPEN=", Kind.SESSION, T),
    _c("CLOSE", Kind.SESSION, T, exact=True),
    _c("CNTLON", Kind.SESSION, T, exact=True),
    _c("CNTLOFF", Kind.SESSION, T, exact=True),
    _c("KEYWD", Kind.SESSION, T),
    _c("PRTVER", Kind.READ, T),  # PRTVERVALS -> QoK1; LISTL/EMDAT variants: thesis only
    # parameters
    _c("PAR", Kind.READ, T),
    _c("PNR", Kind.READ, T),
    _c("PRM=", Kind.EDIT, D),
    _c("PAW=", Kind.EDIT, D),
    # state
    _c("STATE", Kind.READ, T, exact=True),
    _c("DSTATE", Kind.READ, T, exact=True),  # answered by a real CR1-571 [issue 24]
    _c("ERRORRD", Kind.READ, T),
    _c("ERRORMES", Kind.READ, T),
    _c("ERRORLOG", Kind.READ, D),
    _c("ERROR", Kind.READ, C, exact=True),
    _c("STPSIG", Kind.READ, D, exact=True),
    _c("CALIB", Kind.READ, D, exact=True),
    _c("TIME", Kind.READ, T, exact=True),
    _c("PTIME", Kind.READ, T, exact=True),
    _c("JPOSF", Kind.READ, T, slots=_POS, exact=True),
    _c("PPOSF", Kind.READ, T, slots=_POS, exact=True),
    _c("GJPOSF", Kind.READ, T, slots=_POS, exact=True),
    _c("GPPOSF", Kind.READ, T, slots=_POS, exact=True),
    _c("OVRD=", Kind.SETTING, T, rights=True),
    _c("OVRD", Kind.READ, D, exact=True),
    _c("IN", Kind.READ, D),
    _c("OUT=", Kind.MOTION, D),
    _c("OUT", Kind.READ, D),
    _c("HNDSTS", Kind.READ, D, exact=True),
    _c("PRGRD", Kind.READ, D, exact=True),
    _c("LINERD", Kind.READ, D, exact=True),
    # servo, alarms
    _c("SRVON", Kind.POWER, T, rights=True, exact=True),
    _c("SRVOFF", Kind.POWER, C, exact=True),
    _c("RSTALRM", Kind.POWER, C, rights=True, exact=True),
    # motion
    _c("STOP", Kind.STOP, C, slots=frozenset({_S.TASK, _S.ALL})),
    _c("EXEC", Kind.MOTION, C, rights=True, slots=_EDIT),
    _c("JOGST", Kind.READ, T, slots=frozenset({_S.ALL, _S.TASK}), exact=True),
    _c("JOG", Kind.MOTION, D, rights=True),
    _c("HNDON", Kind.MOTION, D),
    _c("HNDOFF", Kind.MOTION, D),
    _c("STEP", Kind.MOTION, D, rights=True),
    _c("ALIGN", Kind.MOTION, D, rights=True),
    _c("MOVSP", Kind.MOTION, D, rights=True),
    _c("HOME", Kind.MOTION, D, rights=True),
    _c("RUN", Kind.MOTION, T, rights=True),
    # HOT<program>;<variable>=<value>: write a variable of a running program [R-protocol
    # manual; sent by ctu-mitsubishi to a real RV-6S, which moves it with J1=(…)].
    _c("HOT", Kind.MOTION, C),
    # program slots
    _c("PRGLOAD=", Kind.PROGRAM, C, rights=True),
    _c("PRGUP", Kind.PROGRAM, D, rights=True),
    _c("PRGDOWN", Kind.PROGRAM, D, rights=True),
    _c("LINENO=", Kind.PROGRAM, D, rights=True),
    _c("BREAKON", Kind.PROGRAM, D, rights=True),
    _c("DATINST", Kind.PROGRAM, D, rights=True),
    _c("SLOTINIT", Kind.PROGRAM, T, rights=True, exact=True),
    _c("RSTPRG", Kind.PROGRAM, C, rights=True, exact=True),
    # program memory
    _c("LOAD=", Kind.EDIT, T),
    _c("NEW", Kind.EDIT, T, exact=True),
    _c("ECLR", Kind.EDIT, T, exact=True),
    _c("EMDAT", Kind.EDIT, T, slots=_EDIT),
    _c("EDATA", Kind.EDIT, T, slots=_EDIT),
    _c("SAVE", Kind.EDIT, T, exact=True),
    _c("FDEL", Kind.EDIT, T),
    _c("LISTL", Kind.READ, C, slots=_EDIT),
    _c("LISTI", Kind.READ, D, slots=_EDIT),
    _c("LISTP", Kind.READ, D, slots=_EDIT),
    _c("PDIR", Kind.READ, T),
    _c("FCHECK", Kind.READ, D),
)
del T, C, D

COMMANDS: Final[Mapping[str, CommandSpec]] = MappingProxyType({c.name: c for c in _TABLE})
"""Command word (or prefix) -> its spec."""

_BY_LENGTH: Final = sorted(_TABLE, key=lambda c: len(c.name), reverse=True)

OVERTAKING_COMMANDS: Final = frozenset({"STOP"})
"""Commands that may be sent while another request is outstanding [DOC S5: STOP always
allowed, needs no operation rights]."""


def lookup(command: str) -> CommandSpec | None:
    """The spec of ``command`` (its text after ``<robot>;<slot>;``), or None if unknown.

    The longest matching name wins (``OVRD=`` before ``OVRD``, ``ERRORMES`` before
    ``ERROR``); an exact command followed by an argument does not match, but a trailing
    ``.`` is no argument (``JPOSF.`` was answered by a real RV-1A [issue 24]).
    """
    upper = command.upper()
    if upper.endswith(".") and not upper.startswith("HOT"):
        upper = upper[:-1]
    for spec in _BY_LENGTH:
        if upper.startswith(spec.name):
            if spec.exact and upper[len(spec.name) :].strip():
                continue
            return spec
    return None


def needs_rights(command: str) -> bool:
    """Whether ``command`` needs the operation rights (unknown commands: no)."""
    spec = lookup(command)
    return spec is not None and spec.rights


class Answer(enum.Enum):
    """What a successful reply to a command carries: how a reply is checked to *fit* its
    request, so a reply that belongs to another request is caught, never passed on."""

    EMPTY = "empty"  # a bare QoK/Qok [TRACE: every one on record]
    DATA = "data"  # some answer text
    ANY = "any"  # not known well enough to check


_EMPTY: Final = frozenset(
    {"CLOSE", "CNTLON", "CNTLOFF", "KEYWD", "SRVON", "SLOTINIT", "RUN", "LOAD=", "NEW"}
    | {"ECLR", "EMDAT", "EDATA", "SAVE", "FDEL", "JOGST"}
)
"""Commands whose QoK carries nothing, every one confirmed by real traffic [TRACE K9b]."""
_DATA: Final = frozenset(
    {"OPEN=", "STATE", "DSTATE", "JPOSF", "PPOSF", "GJPOSF", "GPPOSF", "PAR", "PNR"}
    | {"TIME", "PTIME", "OVRD="}
)
_EDIT_REFUSALS: Final = frozenset({"EMDAT", "EDATA"})


def answer_kind(command: str) -> Answer:
    """`Answer` for ``command`` (ANY when unknown)."""
    spec = lookup(command)
    if spec is None:
        return Answer.ANY
    if spec.name in _EMPTY:
        return Answer.EMPTY
    return Answer.DATA if spec.name in _DATA else Answer.ANY


def fits(request: Request | str, reply: Reply) -> bool:
    """Whether ``reply`` can be the answer to ``request``.

    A refusal fits any request (an edit refusal only EMDAT/EDATA); an answer must have the
    shape its command gives: empty for NEW/EMDAT/SAVE…, ``J1;…`` for JPOSF, ``X;…`` for
    PPOSF, ``RLNG;…`` for ``PARRLNG``, ≥ 12 fields for OPEN, ≥ 5 for STATE.

    >>> fits("EMDAT10 END", Ok("")), fits("EMDAT10 END", Ok("RLNG;1;1")), fits("PARRLNG", Ok(""))
    (True, False, False)
    """
    command = request.command if isinstance(request, Request) else request
    spec = lookup(command)
    if isinstance(reply, EditRefused):
        return spec is not None and spec.name in _EDIT_REFUSALS
    if not isinstance(reply, Ok):
        return True
    kind = answer_kind(command)
    answer = reply.answer
    if kind is Answer.EMPTY:
        return answer == ""
    if kind is Answer.ANY or spec is None:
        return True
    if not answer:
        return False
    name = spec.name
    if name in ("PAR", "PNR"):
        return answer.upper().startswith(command[len(name) :].strip().upper() + ";")
    if name in ("JPOSF", "GJPOSF"):
        return answer.startswith("J1;")
    if name in ("PPOSF", "GPPOSF"):
        return answer.startswith("X;")
    if name == "OPEN=":
        return answer.count(";") >= 11
    if name == "STATE":
        return answer.count(";") >= 4
    return True


RESYNC_COMMAND: Final = "PARRLNG"
"""The request that resynchronises the pairing after a timeout or an unreadable reply: its
answer names itself (``QoKRLNG;1;1`` [TRACE K4a-CR2B]), reads nothing that changes, and
needs no rights, so every reply before it can be dropped as late or stray."""


def changes_nothing(command: str) -> bool:
    """True for commands that neither move, power, select nor write anything
    (what ``melfa doctor`` may send without ``--probe-upload``)."""
    spec = lookup(command)
    return spec is not None and spec.kind in (Kind.SESSION, Kind.READ)
