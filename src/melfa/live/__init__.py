"""The live protocol of ``/api/ws``: every message the server sends and accepts, as pydantic
models in discriminated unions (`messages`), and their JSON Schema (`schema`, committed as
``docs/ws-schema.json``).

Pure (pydantic, no I/O): the web server builds these models, the desktop client parses
them, and the schema is what any other client reads.
"""

from melfa.live.messages import (
    PROTOCOL_VERSION,
    Ack,
    ActorOut,
    AlarmOut,
    ClientMessage,
    CommandResultMessage,
    DebugMessage,
    ErrorMessage,
    Hello,
    JogMessage,
    LeaseMessage,
    LinkMessage,
    ProgressMessage,
    ServerMessage,
    StateMessage,
    StateOut,
    parse_client,
    parse_server,
)

__all__ = [
    "PROTOCOL_VERSION",
    "Ack",
    "ActorOut",
    "AlarmOut",
    "ClientMessage",
    "CommandResultMessage",
    "DebugMessage",
    "ErrorMessage",
    "Hello",
    "JogMessage",
    "LeaseMessage",
    "LinkMessage",
    "ProgressMessage",
    "ServerMessage",
    "StateMessage",
    "StateOut",
    "parse_client",
    "parse_server",
]
