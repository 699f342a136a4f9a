"""The CR2B-574 R-protocol, sans-I/O: bytes in, typed values out, and back.

What it does: hold the controller's facts in one place (error numbers, levels, texts and
their ``L2000`` form in `error_table`, the command table in `commands`, the JOG watchdog and
modes in `jog`, hand numbers and the override range in `limits`, STATE fields and axis names
in `answers`), build and check requests (``<robot>;<slot>;<COMMAND>`` + CR, ≤ 255 bytes),
decode the four reply forms (QoK/Qok/QeR/Qer, 4- or 9-digit error numbers) and the edit
refusal, read ERRORRD/PDIR/PAR answers (`listings`), cut a byte stream into
replies (bounded), read the OPEN/JPOSF/PPOSF/STATE/DSTATE/ERROR answers, pack programs into
EMDAT requests, encode JOG, and name error numbers. The simulator uses the same code to read
requests and write replies, so the two sides cannot drift apart.

What it does not do: no ports, no sockets, no threads, no clock, no timeouts. The link and the
robot client do those. A controller refusal is a value (`Refused`), never an exception here;
exceptions are `LocalProtocolError` (our misuse) and `RemoteProtocolError` (a garbled peer).

Reference: ``docs/protocol.md`` (source tags such as [DOC S1 p.8] are quoted in the code).
"""

from melfa.protocol.answers import (
    JOINT_NAMES,
    POSE_NAMES,
    POSITION_UNKNOWN_TEXT,
    DState,
    ErrorStatus,
    HandStatus,
    ModeKey,
    OpenBanner,
    Position,
    PositionUnknown,
    RunStatus,
    State,
    Status,
    StopStatus,
)
from melfa.protocol.commands import (
    COMMANDS,
    OVERTAKING_COMMANDS,
    CommandSpec,
    Evidence,
    Kind,
    SlotForm,
    changes_nothing,
    lookup,
    needs_rights,
)
from melfa.protocol.connection import ClientConnection, ClientState
from melfa.protocol.emdat import EmdatChunk, chunk_emdat
from melfa.protocol.error_table import (
    ERROR_MESSAGES,
    ErrorCode,
    ErrorInfo,
    ErrorLevel,
    error_code,
    error_level,
    error_text,
)
from melfa.protocol.errors import LocalProtocolError, ProtocolError, RemoteProtocolError
from melfa.protocol.jog import JOG_WATCHDOG_S, Jog, JogInch, JogMode, axis_mask
from melfa.protocol.limits import HANDS, OVERRIDE_PERCENT, span_text
from melfa.protocol.listings import ErrorLogEntry, Parameter, ProgramEntry
from melfa.protocol.messages import (
    CR,
    EDIT_SLOT,
    MAX_COMMAND_BYTES,
    REQUEST_LIMIT,
    TERMINATOR_COUNTS_TOWARDS_LIMIT,
    VT,
    EditRefused,
    Ok,
    Refused,
    Reply,
    Request,
    decode_reply,
    encode_reply,
    parse_request,
)
from melfa.protocol.reader import MAX_REPLY_BYTES, LineSplitter, ReplyReader, RequestReader

__all__ = [
    "COMMANDS",
    "CR",
    "EDIT_SLOT",
    "ERROR_MESSAGES",
    "HANDS",
    "JOG_WATCHDOG_S",
    "JOINT_NAMES",
    "MAX_COMMAND_BYTES",
    "MAX_REPLY_BYTES",
    "OVERRIDE_PERCENT",
    "OVERTAKING_COMMANDS",
    "POSE_NAMES",
    "POSITION_UNKNOWN_TEXT",
    "REQUEST_LIMIT",
    "TERMINATOR_COUNTS_TOWARDS_LIMIT",
    "VT",
    "ClientConnection",
    "ClientState",
    "CommandSpec",
    "DState",
    "EditRefused",
    "EmdatChunk",
    "ErrorCode",
    "ErrorInfo",
    "ErrorLevel",
    "ErrorLogEntry",
    "ErrorStatus",
    "Evidence",
    "HandStatus",
    "Jog",
    "JogInch",
    "JogMode",
    "Kind",
    "LineSplitter",
    "LocalProtocolError",
    "ModeKey",
    "Ok",
    "OpenBanner",
    "Parameter",
    "Position",
    "PositionUnknown",
    "ProgramEntry",
    "ProtocolError",
    "Refused",
    "RemoteProtocolError",
    "Reply",
    "ReplyReader",
    "Request",
    "RequestReader",
    "RunStatus",
    "SlotForm",
    "State",
    "Status",
    "StopStatus",
    "axis_mask",
    "changes_nothing",
    "chunk_emdat",
    "decode_reply",
    "encode_reply",
    "error_code",
    "error_level",
    "error_text",
    "lookup",
    "needs_rights",
    "parse_request",
    "span_text",
]
