"""Requests and replies of the R-protocol as frozen, validated values, and their bytes.

Request framing [DOC S1 p.8 §3.3.1]: ``<robot>;<slot>;<COMMAND><args>`` then the terminator
(CR). Replies [DOC S1 p.8 §3.3.2, CODE/TRACE §2.2 of protocol.md]:

======  ==========================================  =====================================
start   meaning                                     value
======  ==========================================  =====================================
QoK     success, no alarm                           ``Ok(answer)``
Qok     success, an alarm is active                 ``Ok(answer, alarm=True)``
QeR     refused                                     ``Refused(error)``
Qer     refused while an alarm is active            ``Refused(error, alarm=True)``
Qe?     edit refusal ``<err>;<item>;<column>``      ``EditRefused(error, item, column)``
======  ==========================================  =====================================

>>> Request("OPEN=MELFA").to_bytes()
b'1;1;OPEN=MELFA\\r'
>>> parse_request(b"1;9;EMDAT10 MOV P1\\x0b20 END\\r")
Request(command='EMDAT10 MOV P1\\x0b20 END', robot=1, slot=9)
>>> decode_reply(b"Qok4140;2")
Ok(answer='4140;2', alarm=True)
>>> decode_reply(b"Qer4220;2;5")
EditRefused(error=4220, item=2, column=5, alarm=True, detail=None)
>>> decode_reply(b"QeR602000000")  # the real controller's 9-digit form
Refused(error=6020, alarm=False, detail='00000')
>>> decode_reply(b"QeR602000000").code.wire
'602000000'

Strings in the API, bytes on the wire; the conversion happens only here. No I/O, no clock.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Final

from melfa.protocol.error_table import ErrorCode
from melfa.protocol.errors import LocalProtocolError, RemoteProtocolError

CR: Final = b"\r"
LF: Final = b"\n"
VT: Final = "\x0b"
"""Argument / item separator inside EMDAT and LISTL [DOC S1 p.8]."""

MAX_COMMAND_BYTES: Final = 255
"""The controller's command limit [DOC S1 p.6 §3.1]; C6080 / L3270 beyond it."""

TERMINATOR_COUNTS_TOWARDS_LIMIT: Final = True
"""[GUESS] protocol.md §2.1/§8.11: whether the CR counts towards the 255. Unknown, so we take
the safe side: a request is at most 254 bytes *before* its CR. Costs one byte per EMDAT."""

REQUEST_LIMIT: Final = MAX_COMMAND_BYTES - (1 if TERMINATOR_COUNTS_TOWARDS_LIMIT else 0)
"""Largest request we build or accept, in bytes, prefix included, CR excluded."""

ROBOT_NUMBERS: Final = range(4)
"""0–3; 0 means all robots for some commands [DOC S1 §3.3.1]."""
SLOT_NUMBERS: Final = range(-1, 34)
"""0–33; 0 means all slots (``1;0;STOP``) [DOC S1 §3.3.1, CODE S12/S18]; -1 is what RT
ToolBox sends for position reads (``1;-1;PPOSF``) and the controller answers [TRACE K9b-PROG]."""
EDIT_SLOT: Final = 9
"""TASKMAX + 1 with the default TASKMAX 8 [DOC S1; TRACE S10 OPEN banner ends ``;8;``]."""

ENCODING: Final = "latin-1"
"""Replies are decoded byte-for-char so no reply byte can make decoding itself fail."""

_FORBIDDEN_IN_COMMAND = re.compile(r"[\r\n\x00]")


def _check_text(text: str, what: str) -> bytes:
    bad = _FORBIDDEN_IN_COMMAND.search(text)
    if bad is not None:
        raise LocalProtocolError(
            f"{what} contains {bad.group()!r} at column {bad.start() + 1}; "
            "CR, LF and NUL end or break a message"
        )
    try:
        return text.encode("ascii")
    except UnicodeEncodeError as exc:
        raise LocalProtocolError(
            f"{what} contains non-ASCII {text[exc.start]!r} at column {exc.start + 1}; "
            "the controller only takes ASCII"
        ) from None


@dataclass(frozen=True)
class Request:
    """One command for the controller. Valid by construction: if it exists, it fits.

    ``command`` holds the command word and its arguments (``"RUN1;1"``, ``"EXECMOV P1"``).
    """

    command: str
    robot: int = 1
    slot: int = 1

    def __post_init__(self) -> None:
        if self.robot not in ROBOT_NUMBERS:
            raise LocalProtocolError(f"robot number {self.robot} is outside 0–3")
        if self.slot not in SLOT_NUMBERS:
            raise LocalProtocolError(f"slot number {self.slot} is outside -1–33")
        if not self.command:
            raise LocalProtocolError("empty command")
        size = len(_check_text(self.command, "command")) + len(self.prefix)
        if size > REQUEST_LIMIT:
            raise LocalProtocolError(
                f"request is {size} bytes with its prefix; the limit is {REQUEST_LIMIT} "
                f"(255 per [DOC S1 p.6], CR counted: {TERMINATOR_COUNTS_TOWARDS_LIMIT})"
            )

    @property
    def prefix(self) -> str:
        """``<robot>;<slot>;``."""
        return f"{self.robot};{self.slot};"

    @property
    def name(self) -> str:
        """The leading command word, upper case (``"EXECMOV P1"`` -> ``"EXECMOV"``).

        Good enough for logs and dispatch: commands are letters, arguments start at the first
        character that is not a letter (EXEC's argument is the statement; see `exec_statement`).
        """
        match = re.match(r"[A-Za-z]+", self.command)
        return match.group().upper() if match else ""

    def to_bytes(self) -> bytes:
        """Wire form including the CR terminator."""
        return (self.prefix + self.command).encode("ascii") + CR


_PREFIX = re.compile(r"(\d*);(-?\d*);")


def parse_request(data: bytes) -> Request:
    """Decode one request line (simulator side). A trailing CR and/or LF is ignored.

    The prefix fields may be empty (defaults 1) or missing altogether [DOC S1 §3.3.1].
    Raises `RemoteProtocolError` with the controller's error number: 6080 for an over-long
    command, 6010 for anything else unusable.
    """
    line = data.rstrip(b"\r\n")
    if len(line) > REQUEST_LIMIT:
        raise RemoteProtocolError(
            f"request of {len(line)} bytes exceeds {REQUEST_LIMIT}", error_number=6080
        )
    try:
        text = line.decode("ascii")
    except UnicodeDecodeError as exc:
        raise RemoteProtocolError(
            f"non-ASCII byte 0x{line[exc.start]:02x} at column {exc.start + 1}", error_number=6010
        ) from None
    robot = slot = 1
    match = _PREFIX.match(text)
    if match is not None:
        robot = int(match.group(1)) if match.group(1) else 1
        slot = int(match.group(2)) if match.group(2) else 1
        text = text[match.end() :]
    try:
        return Request(text, robot=robot, slot=slot)
    except LocalProtocolError as exc:
        raise RemoteProtocolError(f"bad request {line!r}: {exc}", error_number=6010) from None


@dataclass(frozen=True)
class Ok:
    """``QoK<answer>`` (``alarm=False``) or ``Qok<answer>`` (an alarm is active)."""

    answer: str = ""
    alarm: bool = False

    def __post_init__(self) -> None:
        if _FORBIDDEN_IN_COMMAND.search(self.answer):
            raise LocalProtocolError("reply answer contains CR, LF or NUL")
        try:
            self.answer.encode(ENCODING)
        except UnicodeEncodeError:
            raise LocalProtocolError(f"reply answer is not {ENCODING} text") from None


@dataclass(frozen=True)
class Refused:
    """``QeR<error>`` or, with an alarm active, ``Qer<error>``. Data, not an exception.

    ``detail`` is None for the manual's 4-digit form (``QeR6020``) and the 5 detail digits
    of the real controller's 9-digit form (``QeR602000000`` -> 6020, ``"00000"``) [TRACE
    K9b]. `code` gives the number exactly as received, for ``ERRORMES``.
    """

    error: int
    alarm: bool = False
    detail: str | None = None

    def __post_init__(self) -> None:
        _check_code(self.error, self.detail)

    @property
    def code(self) -> ErrorCode:
        """Number and detail digits, as the controller sent them."""
        return ErrorCode(self.error, self.detail)

    @classmethod
    def of(cls, code: ErrorCode, *, alarm: bool = False) -> Refused:
        """The refusal carrying ``code`` (4- or 9-digit form as ``code`` has it)."""
        return cls(code.number, alarm, code.detail)


def _check_code(error: int, detail: str | None) -> None:
    if not 0 <= error <= 9999:
        raise LocalProtocolError(f"error number {error} is not 0–9999")
    if detail is not None and not (len(detail) == 5 and detail.isdigit() and detail.isascii()):
        raise LocalProtocolError(f"error detail {detail!r} is not 5 digits")


@dataclass(frozen=True)
class EditRefused:
    """A program-edit refusal [DOC S1 §5.2.7–5.2.8].

    EMDAT: ``Qer<error>;<item>;<column>`` (``item`` is the 1-based index of the bad line in the
    batch [GUESS: 1-based]); EDATA: ``Qer<error>;<column>`` (``item`` is None). The manual
    writes this form with a lower-case ``r``, hence the default ``alarm=True``; when decoding,
    the letter's case decides, as for every reply.
    """

    error: int
    item: int | None
    column: int
    alarm: bool = True
    detail: str | None = None

    @property
    def code(self) -> ErrorCode:
        """Number and detail digits, as the controller sent them."""
        return ErrorCode(self.error, self.detail)

    def __post_init__(self) -> None:
        _check_code(self.error, self.detail)
        if self.column < 0 or (self.item is not None and self.item < 0):
            raise LocalProtocolError("edit refusal positions must be ≥ 0")


Reply = Ok | Refused | EditRefused

_HEADS: Final = {"QoK": (True, False), "Qok": (True, True), "QeR": (False, False)}
_HEADS_ALL: Final = {**_HEADS, "Qer": (False, True)}
_REFUSAL = re.compile(r"(\d{9}|\d{1,4})(?:;(\d{1,6}))?(?:;(\d{1,6}))?")


def decode_reply(line: bytes) -> Reply:
    """Decode one reply line (terminator already removed).

    Raises `RemoteProtocolError` for anything that is not one of the four forms.
    """
    text = line.decode(ENCODING)
    head, body = text[:3], text[3:]
    kind = _HEADS_ALL.get(head)
    if kind is None:
        raise RemoteProtocolError(f"reply does not start with QoK/Qok/QeR/Qer: {line[:40]!r}")
    ok, alarm = kind
    if ok:
        if "\x00" in body or "\r" in body or "\n" in body:
            raise RemoteProtocolError(f"reply contains a control character: {line[:40]!r}")
        return Ok(body, alarm)
    match = _REFUSAL.fullmatch(body)
    if match is None:
        raise RemoteProtocolError(f"refusal without a valid error number: {line[:40]!r}")
    code = ErrorCode.parse(match.group(1))
    if match.group(3) is not None:
        return EditRefused(
            code.number, int(match.group(2)), int(match.group(3)), alarm, code.detail
        )
    if match.group(2) is not None:
        return EditRefused(code.number, None, int(match.group(2)), alarm, code.detail)
    return Refused(code.number, alarm, code.detail)


def encode_reply(reply: Reply, terminator: bytes = CR) -> bytes:
    """Wire form of a reply (simulator side). ``terminator`` is CR or CR LF (CTERM232)."""
    if isinstance(reply, Ok):
        head = "Qok" if reply.alarm else "QoK"
        return (head + reply.answer).encode(ENCODING) + terminator
    head = "Qer" if reply.alarm else "QeR"
    if isinstance(reply, EditRefused):
        fields = [reply.code.wire]
        if reply.item is not None:
            fields.append(str(reply.item))
        fields.append(str(reply.column))
        return (head + ";".join(fields)).encode("ascii") + terminator
    return f"{head}{reply.code.wire}".encode("ascii") + terminator
