"""The JSON Schema of ``/api/ws``, committed as ``docs/ws-schema.json`` (a test keeps it
current, like ``docs/openapi.json``). Regenerate::

    python -c 'import json; from melfa.live.schema import ws_schema; \
print(json.dumps(ws_schema(), indent=2))' > docs/ws-schema.json

One document: ``$defs/ServerMessage`` is everything the server sends, ``$defs/ClientMessage``
everything it accepts; each message is one ``$defs`` entry named after its model.
"""

from __future__ import annotations

from typing import Any

from melfa.live.messages import CLIENT, PROTOCOL_VERSION, SERVER

REF = "#/$defs/{model}"


def ws_schema() -> dict[str, Any]:
    """The schema document (JSON Schema 2020-12)."""
    server = SERVER.json_schema(ref_template=REF)
    client = CLIENT.json_schema(ref_template=REF)
    defs: dict[str, Any] = {}
    for part in (server, client):
        for name, definition in part.pop("$defs", {}).items():
            assert defs.get(name, definition) == definition, f"two models named {name}"
            defs[name] = definition
    defs["ServerMessage"] = {"description": "Everything the server sends.", **server}
    defs["ClientMessage"] = {"description": "Everything the server accepts.", **client}
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": f"melfa /api/ws, protocol {PROTOCOL_VERSION}",
        "description": "The messages of melfa's WebSocket (docs/api.md). Each is a JSON "
        "object with a `type`.",
        "anyOf": [
            {"$ref": REF.format(model="ServerMessage")},
            {"$ref": REF.format(model="ClientMessage")},
        ],
        "$defs": dict(sorted(defs.items())),
    }


__all__ = ["ws_schema"]
