"""The CR2B-574 R-protocol, sans-I/O: bytes in, typed values out, and back.

What it does: build and check requests (``<robot>;<slot>;<COMMAND>`` + CR, ≤ 255 bytes),
decode the four reply forms (QoK/Qok/QeR/Qer) and the edit refusal, cut a byte stream into
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
    DState,
    ErrorLevel,
    ErrorStatus,
    OpenBanner,
    Position,
    RunStatus,
    State,
    Status,
    StopStatus,
)
from melfa.protocol.connection import OVERTAKING_COMMANDS, ClientConnection, ClientState
from melfa.protocol.emdat import EmdatChunk, chunk_emdat
from melfa.protocol.error_table import ERROR_MESSAGES, ErrorInfo, error_text
from melfa.protocol.errors import LocalProtocolError, ProtocolError, RemoteProtocolError
from melfa.protocol.jog import JOG_WATCHDOG_S, Jog, JogInch, JogMode, axis_mask
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
    "CR",
    "EDIT_SLOT",
    "ERROR_MESSAGES",
    "JOG_WATCHDOG_S",
    "JOINT_NAMES",
    "MAX_COMMAND_BYTES",
    "MAX_REPLY_BYTES",
    "OVERTAKING_COMMANDS",
    "POSE_NAMES",
    "REQUEST_LIMIT",
    "TERMINATOR_COUNTS_TOWARDS_LIMIT",
    "VT",
    "ClientConnection",
    "ClientState",
    "DState",
    "EditRefused",
    "EmdatChunk",
    "ErrorInfo",
    "ErrorLevel",
    "ErrorStatus",
    "Jog",
    "JogInch",
    "JogMode",
    "LineSplitter",
    "LocalProtocolError",
    "Ok",
    "OpenBanner",
    "Position",
    "ProtocolError",
    "Refused",
    "RemoteProtocolError",
    "Reply",
    "ReplyReader",
    "Request",
    "RequestReader",
    "RunStatus",
    "State",
    "Status",
    "StopStatus",
    "axis_mask",
    "chunk_emdat",
    "decode_reply",
    "encode_reply",
    "error_text",
    "parse_request",
]
